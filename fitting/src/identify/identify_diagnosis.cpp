// Residual description: component and load-case RMS, load dependence, low-order spatial modes.
#include "isospring/fitting/identify_diagnosis.hpp"

#include <Eigen/QR>
#include <cmath>
#include <cstdio>
#include <limits>

namespace isospring::fitting {

namespace {

std::string percent(double x) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.1f%%", 100.0 * x);
  return buffer;
}

}  // namespace

ResidualDescription describe_residual(const std::vector<Eigen::Vector3d>& positions,
                                      const std::vector<Eigen::Vector3d>& residuals,
                                      const std::vector<int>& group,
                                      const std::vector<std::string>& case_ids,
                                      const std::vector<Eigen::VectorXd>& case_loads, int dimension,
                                      const Eigen::Vector3d& centre, double length) {
  const int dim = dimension;
  ResidualDescription d;
  d.dimension = dim;
  const size_t cases = case_ids.size();
  std::vector<std::vector<size_t>> members(cases);
  for (size_t m = 0; m < residuals.size(); ++m) members[static_cast<size_t>(group[m])].push_back(m);

  double total = 0.0, constant = 0.0, linear = 0.0;
  int rows = 0, modes = 0;
  Eigen::Vector3d component_sum = Eigen::Vector3d::Zero();
  for (size_t l = 0; l < cases; ++l) {
    ResidualCaseDescription c;
    c.id = case_ids[l];
    c.markers = static_cast<int>(members[l].size());
    const Eigen::VectorXd& f = case_loads[l];
    c.load_norm = f.norm();
    for (Eigen::Index k = 0; k < f.size(); ++k) c.resultant[static_cast<int>(k % dim)] += f[k];
    const auto n = static_cast<Eigen::Index>(members[l].size());
    if (n == 0) {
      d.load_cases.push_back(c);
      continue;
    }
    // Basis per component: 1, (x - x_c) / L, (y - y_c) / L (, (z - z_c) / L).
    Eigen::MatrixXd basis(n, 1 + dim);
    Eigen::MatrixXd r(n, dim);
    for (Eigen::Index i = 0; i < n; ++i) {
      const size_t m = members[l][static_cast<size_t>(i)];
      basis(i, 0) = 1.0;
      for (int a = 0; a < dim; ++a) {
        basis(i, 1 + a) = (positions[m][a] - centre[a]) / length;
        r(i, a) = residuals[m][a];
      }
    }
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(basis);
    const Eigen::Index rank = qr.rank();  // markers on a line or a plane have fewer modes
    const Eigen::MatrixXd q =
        (qr.householderQ() * Eigen::MatrixXd::Identity(n, basis.cols())).leftCols(rank);
    for (int a = 0; a < dim; ++a) {
      const Eigen::VectorXd ra = r.col(a);
      const double energy = ra.squaredNorm();
      const double mean = ra.mean();
      const double explained = (q.transpose() * ra).squaredNorm();
      total += energy;
      constant += n * mean * mean;
      linear += std::max(0.0, explained - n * mean * mean);
      c.component_rms[a] = std::sqrt(energy / n);
      component_sum[a] += energy;
    }
    rows += static_cast<int>(n) * dim;
    modes += static_cast<int>(rank) * dim;
    c.rms = std::sqrt(r.squaredNorm() / (static_cast<double>(n) * dim));
    c.rms_per_load = c.load_norm > 0.0 ? c.rms / c.load_norm : 0.0;
    d.load_cases.push_back(c);
  }
  const int markers_total = static_cast<int>(residuals.size());
  d.rms = rows > 0 ? std::sqrt(total / rows) : 0.0;
  for (int a = 0; a < dim; ++a)
    d.component_rms[a] = markers_total > 0 ? std::sqrt(component_sum[a] / markers_total) : 0.0;
  d.constant_fraction = total > 0.0 ? constant / total : 0.0;
  d.linear_fraction = total > 0.0 ? linear / total : 0.0;
  d.noise_fraction = rows > 0 ? static_cast<double>(modes) / rows : 0.0;

  d.load_correlation = std::numeric_limits<double>::quiet_NaN();
  if (cases >= 3) {
    double mx = 0, my = 0;
    for (const auto& c : d.load_cases) mx += c.load_norm, my += c.rms;
    mx /= cases;
    my /= cases;
    double sxy = 0, sxx = 0, syy = 0;
    for (const auto& c : d.load_cases) {
      sxy += (c.load_norm - mx) * (c.rms - my);
      sxx += (c.load_norm - mx) * (c.load_norm - mx);
      syy += (c.rms - my) * (c.rms - my);
    }
    if (sxx > 0 && syy > 0) d.load_correlation = sxy / std::sqrt(sxx * syy);
  }

  // One sentence: where the energy is, against what noise alone would give.
  int largest = 0;
  for (int a = 1; a < dim; ++a)
    if (d.component_rms[a] > d.component_rms[largest]) largest = a;
  const double smooth = d.constant_fraction + d.linear_fraction;
  d.summary =
      "constant and linear modes per load case and component explain " + percent(smooth) +
      " of the residual energy (constant " + percent(d.constant_fraction) + ", linear " +
      percent(d.linear_fraction) + "; pure noise: about " + percent(d.noise_fraction) + "), " +
      (smooth > 0.5 ? "a smooth misfit (a rigid motion, a uniform strain or another slowly varying "
                      "field)"
       : smooth > 3.0 * d.noise_fraction ? "partly smooth"
                                         : "no more than noise would put there") +
      "; largest component " + std::string(1, "xyz"[largest]) + ".";
  return d;
}

}  // namespace isospring::fitting
