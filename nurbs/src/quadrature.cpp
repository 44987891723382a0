#include "isospring/nurbs/quadrature.hpp"

#include <cmath>
#include <map>
#include <numbers>

#include "isospring/nurbs/error.hpp"

namespace isospring::nurbs {

GaussRule gauss_legendre(int n) {
  if (n < 1 || n > 64)
    throw InputError("Gauss-Legendre rule: use 1 to 64 points, got " + std::to_string(n));
  GaussRule rule;
  rule.points.resize(static_cast<size_t>(n));
  rule.weights.resize(static_cast<size_t>(n));
  // Roots are symmetric; find the upper half by Newton from the Chebyshev-like initial guess.
  for (int i = 0; i < (n + 1) / 2; ++i) {
    double x = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5));
    double derivative = 0.0;
    for (int iteration = 0; iteration < 100; ++iteration) {
      double p0 = 1.0, p1 = x;  // Legendre recurrence P_k
      for (int k = 2; k <= n; ++k) {
        const double pk = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = pk;
      }
      if (n == 1) p0 = 1.0;
      derivative = n * (x * p1 - p0) / (x * x - 1.0);
      const double step = p1 / derivative;
      x -= step;
      if (std::abs(step) < 1e-16) break;
    }
    // Recompute the derivative at the converged root for the weight.
    double p0 = 1.0, p1 = x;
    for (int k = 2; k <= n; ++k) {
      const double pk = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
      p0 = p1;
      p1 = pk;
    }
    derivative = n == 1 ? 1.0 : n * (x * p1 - p0) / (x * x - 1.0);
    const double weight = 2.0 / ((1.0 - x * x) * derivative * derivative);
    rule.points[static_cast<size_t>(i)] = -x;
    rule.points[static_cast<size_t>(n - 1 - i)] = x;
    rule.weights[static_cast<size_t>(i)] = weight;
    rule.weights[static_cast<size_t>(n - 1 - i)] = weight;
  }
  if (n % 2 == 1) rule.points[static_cast<size_t>(n / 2)] = 0.0;
  return rule;
}

const GaussRule& gauss_legendre_cached(int n) {
  static thread_local std::map<int, GaussRule> rules;
  auto found = rules.find(n);
  if (found == rules.end()) found = rules.emplace(n, gauss_legendre(n)).first;
  return found->second;
}

}  // namespace isospring::nurbs
