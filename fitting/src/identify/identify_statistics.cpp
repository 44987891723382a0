// Statistics of the identification: the F-test tail and the column-scaled Gauss-Newton covariance
// (the noise estimate: noise_estimate.cpp).
#include <Eigen/SVD>
#include <algorithm>
#include <boost/math/distributions/fisher_f.hpp>
#include <cmath>
#include <limits>

#include "isospring/fitting/identify.hpp"

namespace isospring::fitting {

double f_test_p_value(double f, int d1, int d2) {
  if (d1 <= 0 || d2 <= 0) return 1.0;
  if (!(f > 0.0)) return 1.0;
  if (!std::isfinite(f)) return 0.0;
  const boost::math::fisher_f distribution(d1, d2);
  return boost::math::cdf(boost::math::complement(distribution, f));
}

Eigen::MatrixXd gauss_newton_covariance(const Eigen::MatrixXd& weighted_jacobian,
                                        double relative_tolerance) {
  const Eigen::Index p = weighted_jacobian.cols();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Eigen::VectorXd scale(p);
  for (Eigen::Index j = 0; j < p; ++j) {
    const double norm = weighted_jacobian.col(j).norm();
    scale[j] = norm > 0.0 ? 1.0 / norm : 0.0;
  }
  const Eigen::MatrixXd scaled = weighted_jacobian * scale.asDiagonal();
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(scaled, Eigen::ComputeThinV);
  const Eigen::VectorXd& s = svd.singularValues();
  const Eigen::MatrixXd& v = svd.matrixV();
  const double largest = s.size() > 0 ? s[0] : 0.0;
  Eigen::VectorXd inverse_square = Eigen::VectorXd::Zero(s.size());
  std::vector<bool> unidentifiable(static_cast<size_t>(p), false);
  for (Eigen::Index k = 0; k < s.size(); ++k) {
    if (s[k] > relative_tolerance * largest) {
      inverse_square[k] = 1.0 / (s[k] * s[k]);
      continue;
    }
    for (Eigen::Index j = 0; j < p; ++j)
      if (std::abs(v(j, k)) > 1e-6) unidentifiable[static_cast<size_t>(j)] = true;
  }
  // Fewer rows than parameters: V is p x rows, the missing directions are a null space too.
  if (s.size() < p) unidentifiable.assign(static_cast<size_t>(p), true);
  Eigen::MatrixXd covariance =
      scale.asDiagonal() * (v * inverse_square.asDiagonal() * v.transpose()) * scale.asDiagonal();
  for (Eigen::Index j = 0; j < p; ++j)
    if (unidentifiable[static_cast<size_t>(j)] || scale[j] == 0.0) {
      covariance.row(j).setConstant(nan);
      covariance.col(j).setConstant(nan);
    }
  return covariance;
}

}  // namespace isospring::fitting
