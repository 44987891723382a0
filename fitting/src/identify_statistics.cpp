// Statistics of the identification: the F-test tail and the nearest-neighbour noise estimate.
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

double estimate_noise(const std::vector<Eigen::Vector3d>& positions,
                      const std::vector<Eigen::Vector3d>& residuals, const std::vector<int>& group,
                      int dimension) {
  std::vector<double> differences;
  const size_t n = positions.size();
  for (size_t m = 0; m < n; ++m) {
    size_t nearest = n;
    double best = std::numeric_limits<double>::infinity();
    for (size_t k = 0; k < n; ++k) {
      if (k == m || group[k] != group[m]) continue;
      const double d = (positions[k] - positions[m]).squaredNorm();
      if (d < best) {
        best = d;
        nearest = k;
      }
    }
    if (nearest == n) continue;
    for (int c = 0; c < dimension; ++c)
      differences.push_back(std::abs(residuals[m][c] - residuals[nearest][c]));
  }
  if (differences.empty()) return 0.0;
  auto middle = differences.begin() + static_cast<std::ptrdiff_t>(differences.size() / 2);
  std::nth_element(differences.begin(), middle, differences.end());
  // MAD of a difference of two independent N(0, s^2) values: 0.6745 sqrt(2) s.
  return 1.482602218505602 * *middle / std::sqrt(2.0);
}

}  // namespace isospring::fitting
