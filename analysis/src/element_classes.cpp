// Classes of elements with equal integrals on affine patches (element_classes.hpp).
#include "element_classes.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>

namespace isospring::analysis::detail {

namespace {

// Greville abscissa of basis function i: the mean of knots i+1 .. i+p (the knot itself for p = 0).
double greville(const nurbs::KnotVector& knots, int i) {
  const int p = knots.degree();
  if (p == 0) return 0.5 * (knots[i] + knots[i + 1]);
  double sum = 0;
  for (int k = 1; k <= p; ++k) sum += knots[i + k];
  return sum / p;
}

// Class index of each element of one direction: elements with the same knots t_{s-p+1} ..
// t_{s+p} relative to t_s (s the element's span) share a class.
std::vector<int> direction_classes(const DirectionRule& rule, const nurbs::KnotVector& knots) {
  const int p = rule.degree;
  const double tolerance = 1e-13 * std::max(1.0, std::abs(knots.last() - knots.first()));
  std::vector<std::vector<double>> keys;
  std::vector<int> classes;
  for (int span : rule.spans) {
    std::vector<double> key;
    for (int k = span - p + 1; k <= span + p; ++k) key.push_back(knots[k] - knots[span]);
    int found = -1;
    for (size_t c = 0; c < keys.size() && found < 0; ++c) {
      bool same = true;
      for (size_t k = 0; k < key.size() && same; ++k)
        same = std::abs(key[k] - keys[c][k]) <= tolerance;
      if (same) found = static_cast<int>(c);
    }
    if (found < 0) {
      found = static_cast<int>(keys.size());
      keys.push_back(std::move(key));
    }
    classes.push_back(found);
  }
  return classes;
}

}  // namespace

bool affine_patch(const nurbs::Patch& patch) {
  const int dim = patch.param_dim();
  const int count = patch.num_points();
  const double w0 = patch.weight(0);
  for (double w : patch.weights())
    if (std::abs(w - w0) > 1e-14 * std::abs(w0)) return false;
  // Least squares of the control points on [greville, 1]; the fit is exact for an affine map.
  Eigen::MatrixXd design(count, dim + 1);
  Eigen::MatrixXd points(count, 3);
  for (int index = 0; index < count; ++index) {
    const std::array<int, 3> at = patch.net_position(index);
    for (int d = 0; d < dim; ++d)
      design(index, d) = greville(patch.knots(d), at[static_cast<size_t>(d)]);
    design(index, dim) = 1.0;
    points.row(index) = patch.control_point(index).transpose();
  }
  const Eigen::MatrixXd map = design.colPivHouseholderQr().solve(points);
  const double extent = (points.colwise().maxCoeff() - points.colwise().minCoeff()).norm();
  return ((design * map - points).cwiseAbs().maxCoeff() <= 1e-12 * extent);
}

ElementClasses affine_element_classes(const PatchQuadrature& quadrature) {
  ElementClasses out;
  const nurbs::Patch& patch = quadrature.patch();
  if (!affine_patch(patch)) return out;
  const int dim = patch.param_dim();
  std::array<std::vector<int>, 3> classes;
  std::array<int, 3> counts{1, 1, 1};
  for (int d = 0; d < dim; ++d) {
    classes[static_cast<size_t>(d)] = direction_classes(quadrature.rule(d), patch.knots(d));
    counts[static_cast<size_t>(d)] = 1 + *std::max_element(classes[static_cast<size_t>(d)].begin(),
                                                           classes[static_cast<size_t>(d)].end());
  }
  out.first.assign(static_cast<size_t>(counts[0] * counts[1] * counts[2]), -1);
  out.of_element.resize(static_cast<size_t>(quadrature.num_elements()));
  for (int e = 0; e < quadrature.num_elements(); ++e) {
    const std::array<int, 3> at = quadrature.element_position(e);
    int key = 0;
    for (int d = dim - 1; d >= 0; --d)
      key = key * counts[static_cast<size_t>(d)] +
            classes[static_cast<size_t>(d)][static_cast<size_t>(at[static_cast<size_t>(d)])];
    out.of_element[static_cast<size_t>(e)] = key;
    if (out.first[static_cast<size_t>(key)] < 0) out.first[static_cast<size_t>(key)] = e;
  }
  return out;
}

}  // namespace isospring::analysis::detail
