#include "isospring/geometry/measure.hpp"

#include <array>
#include <cmath>

#include "isospring/geometry/construction.hpp"
#include "isospring/nurbs/quadrature.hpp"

namespace isospring::geometry {

namespace {
struct Rule1D {
  std::vector<double> points, weights;
};

// Quadrature nodes and weights covering a whole knot vector.
Rule1D rule_along(const nurbs::KnotVector& knots, const nurbs::GaussRule& gauss, int parts) {
  Rule1D rule;
  const std::vector<double> breaks = knots.unique();
  for (size_t e = 0; e + 1 < breaks.size(); ++e) {
    const double h = (breaks[e + 1] - breaks[e]) / parts;
    for (int s = 0; s < parts; ++s) {
      const double a = breaks[e] + s * h;
      for (size_t g = 0; g < gauss.points.size(); ++g) {
        rule.points.push_back(a + (gauss.points[g] + 1.0) * h / 2.0);
        rule.weights.push_back(gauss.weights[g] * h / 2.0);
      }
    }
  }
  return rule;
}
}  // namespace

double measure(const nurbs::Patch& patch, const MeasureRule& rule) {
  const nurbs::GaussRule gauss = nurbs::gauss_legendre(rule.points);
  std::array<Rule1D, 3> rules;
  for (int d = 0; d < 3; ++d)
    rules[static_cast<size_t>(d)] = d < patch.param_dim()
                                        ? rule_along(patch.knots(d), gauss, rule.subdivisions)
                                        : Rule1D{{0.0}, {1.0}};
  double total = 0.0;
  for (size_t k = 0; k < rules[2].points.size(); ++k)
    for (size_t j = 0; j < rules[1].points.size(); ++j) {
      double row = 0.0;  // partial sums keep round-off small on fine rules
      for (size_t i = 0; i < rules[0].points.size(); ++i)
        row += rules[0].weights[i] *
               std::abs(jacobian_determinant(
                   patch, {rules[0].points[i], rules[1].points[j], rules[2].points[k]}));
      total += rules[1].weights[j] * rules[2].weights[k] * row;
    }
  return total;
}

double measure(const std::vector<nurbs::Patch>& patches, const MeasureRule& rule) {
  double total = 0.0;
  for (const auto& patch : patches) total += measure(patch, rule);
  return total;
}

}  // namespace isospring::geometry
