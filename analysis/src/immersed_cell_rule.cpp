// Reduced cell rules (immersed_cell_rule.hpp).
#include "immersed_cell_rule.hpp"

#include <array>

#include "isospring/nurbs/basis.hpp"
#include "isospring/nurbs/quadrature.hpp"

namespace isospring::analysis::detail {

namespace {

// The Lagrange polynomials of the nodes at t, c_i prod_{j != i} (t - t_j) with c_i the inverse
// of prod_{j != i} (t_i - t_j). The nodes are Gauss points, whose Lebesgue constant stays small,
// so the reduced weights lose no more than a few ulps of the cell's volume.
struct Lagrange {
  std::vector<double> nodes, scale;
  explicit Lagrange(const std::vector<double>& t) : nodes(t), scale(t.size(), 1.0) {
    for (size_t i = 0; i < t.size(); ++i)
      for (size_t j = 0; j < t.size(); ++j)
        if (j != i) scale[i] /= t[i] - t[j];
  }
  void operator()(double t, double* out) const {
    for (size_t i = 0; i < nodes.size(); ++i) {
      double l = scale[i];
      for (size_t j = 0; j < nodes.size(); ++j)
        if (j != i) l *= t - nodes[j];
      out[i] = l;
    }
  }
};

}  // namespace

CellRule reduced_cell_rule(const BackgroundBasis& basis, const Element& e,
                           const std::vector<Eigen::Vector3d>& points,
                           const std::vector<double>& weights) {
  const int dim = basis.dim();
  std::array<int, 3> n{1, 1, 1};
  for (int d = 0; d < dim; ++d) n[static_cast<size_t>(d)] = 2 * basis.degree(d) + 1;
  const size_t reduced = static_cast<size_t>(n[0] * n[1] * n[2]);
  if (reduced >= points.size()) return {points, weights};

  const Eigen::Vector3d lo = basis.element_lo(e), hi = basis.element_hi(e);
  std::array<std::vector<double>, 3> nodes;
  std::vector<Lagrange> polynomials;
  for (int d = 0; d < dim; ++d) {
    nodes[static_cast<size_t>(d)] = nurbs::gauss_legendre_cached(n[static_cast<size_t>(d)]).points;
    polynomials.emplace_back(nodes[static_cast<size_t>(d)]);
  }
  CellRule rule;
  rule.weights.assign(reduced, 0.0);
  // Beyond the dimension (2D) the single node is the cells' plane and its Lagrange polynomial 1.
  std::array<std::array<double, 2 * nurbs::kMaxDegree + 1>, 3> l{};
  for (auto& row : l) row[0] = 1.0;
  for (size_t q = 0; q < points.size(); ++q) {
    const Eigen::Vector3d y = basis.to_grid(points[q]);  // the element's bounds are grid ones
    for (int d = 0; d < dim; ++d)
      polynomials[static_cast<size_t>(d)]((2.0 * y[d] - lo[d] - hi[d]) / (hi[d] - lo[d]),
                                          l[static_cast<size_t>(d)].data());
    size_t k = 0;
    for (int z = 0; z < n[2]; ++z)
      for (int y = 0; y < n[1]; ++y) {
        const double wyz = weights[q] * l[2][static_cast<size_t>(z)] * l[1][static_cast<size_t>(y)];
        for (int x = 0; x < n[0]; ++x, ++k) rule.weights[k] += wyz * l[0][static_cast<size_t>(x)];
      }
  }
  rule.points.reserve(reduced);
  for (int z = 0; z < n[2]; ++z)
    for (int y = 0; y < n[1]; ++y)
      for (int x = 0; x < n[0]; ++x) {
        Eigen::Vector3d p = basis.to_grid(points.front());  // beyond the dimension: the plane
        const std::array<int, 3> i{x, y, z};
        for (int d = 0; d < dim; ++d)
          p[d] = 0.5 * (lo[d] + hi[d]) +
                 0.5 * (hi[d] - lo[d]) *
                     nodes[static_cast<size_t>(d)][static_cast<size_t>(i[static_cast<size_t>(d)])];
        rule.points.push_back(basis.to_world(p));
      }
  return rule;
}

}  // namespace isospring::analysis::detail
