// The noise level of marker data from the residual of a model that may still miss smooth effects
// (identify.hpp, "Noise level"): local linear fits over each marker's nearest neighbours.
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <numeric>

#include "isospring/fitting/identify.hpp"

namespace isospring::fitting {

namespace {

// Neighbourhood size: a linear function of position has at most 4 coefficients; 12 points leave
// at least 8 residual degrees of freedom, and a neighbourhood small enough that a smooth misfit's
// curvature across it stays far below the noise on marker grids as dense as DIC or FE nodes.
constexpr size_t kNeighbourhood = 12;

}  // namespace

double estimate_noise(const std::vector<Eigen::Vector3d>& positions,
                      const std::vector<Eigen::Vector3d>& residuals, const std::vector<int>& group,
                      int dimension) {
  const size_t n = positions.size();
  std::vector<double> samples;
  std::vector<size_t> others;
  std::vector<double> distance(n);
  for (size_t m = 0; m < n; ++m) {
    others.clear();
    for (size_t k = 0; k < n; ++k)
      if (k != m && group[k] == group[m]) {
        others.push_back(k);
        distance[k] = (positions[k] - positions[m]).squaredNorm();
      }
    const size_t count = std::min(kNeighbourhood - 1, others.size());
    std::partial_sort(others.begin(), others.begin() + static_cast<std::ptrdiff_t>(count),
                      others.end(), [&](size_t a, size_t b) { return distance[a] < distance[b]; });
    if (count < 4) continue;
    // Design: [1, (x - x_m) / radius] over the marker (row 0) and its neighbours; the scaling
    // keeps the rank decision independent of units.
    const double radius = std::sqrt(distance[others[count - 1]]);
    if (!(radius > 0.0)) continue;
    const auto rows = static_cast<Eigen::Index>(count + 1);
    Eigen::MatrixXd design(rows, 4);
    design.row(0) << 1.0, 0.0, 0.0, 0.0;
    for (size_t i = 0; i < count; ++i) {
      const Eigen::Vector3d d = (positions[others[i]] - positions[m]) / radius;
      design.row(static_cast<Eigen::Index>(i) + 1) << 1.0, d.x(), d.y(), d.z();
    }
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(design);
    qr.setThreshold(1e-8);
    const Eigen::Index rank = qr.rank();
    if (rows - rank < 3) continue;  // too few residual degrees of freedom
    const Eigen::MatrixXd q =
        (qr.householderQ() * Eigen::MatrixXd::Identity(rows, rank)).leftCols(rank);
    const double leverage = q.row(0).squaredNorm();  // h_mm of the hat matrix Q Q^T
    if (!(leverage < 1.0 - 1e-9)) continue;
    for (int c = 0; c < dimension; ++c) {
      Eigen::VectorXd r(rows);
      r[0] = residuals[m][c];
      for (size_t i = 0; i < count; ++i)
        r[static_cast<Eigen::Index>(i) + 1] = residuals[others[i]][c];
      const double misfit = r[0] - q.row(0).dot(q.transpose() * r);  // ((I - Q Q^T) r)_0
      samples.push_back(std::abs(misfit) / std::sqrt(1.0 - leverage));
    }
  }
  if (samples.empty()) return 0.0;
  auto middle = samples.begin() + static_cast<std::ptrdiff_t>(samples.size() / 2);
  std::nth_element(samples.begin(), middle, samples.end());
  return 1.482602218505602 * *middle;  // MAD of N(0, s^2) samples: 0.6745 s
}

}  // namespace isospring::fitting
