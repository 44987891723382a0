// Ghost penalty: gamma (lambda + 2 mu) h^(2p-1) / (p!)^2 int_F [d^p u/dn^p].[d^p v/dn^p] on the
// grid faces of badly cut cells shared with another active cell (why: immersed.hpp). The 1/(p!)^2
// makes gamma mean the same for every degree (the p-th derivative of a degree-p B-spline jumps
// by ~p!/h^p).
#include <cmath>
#include <unordered_map>
#include <utility>

#include "immersed_kernels.hpp"
#include "isospring/geometry/immersed_domain.hpp"
#include "isospring/nurbs/quadrature.hpp"

namespace isospring::analysis::detail {

std::set<std::pair<int, int>> ghost_faces(const ImmersedContext& context) {
  const auto& basis = context.basis;
  std::set<std::pair<int, int>> faces;
  for (size_t c = 0; c < context.domain->cells.size(); ++c) {
    const auto& cell = context.domain->cells[c];
    if (cell.kind != geometry::CellKind::kCut) continue;
    const Element& e = context.cell_elements[c];
    double part = 0;
    for (double w : cell.weights) part += w;
    const Eigen::Vector3d size = basis.element_hi(e) - basis.element_lo(e);
    double volume = 1;
    for (int d = 0; d < basis.dim(); ++d) volume *= size[d];
    if (part >= context.options->ghost_fraction * volume) continue;
    for (int d = 0; d < basis.dim(); ++d)
      for (int step : {-1, 1}) {
        Element other = e;
        other[static_cast<size_t>(d)] += step;
        if (other[static_cast<size_t>(d)] < 0 || other[static_cast<size_t>(d)] >= basis.elements(d))
          continue;
        if (context.cell_of_element[static_cast<size_t>(basis.flat(other))] < 0) continue;
        faces.emplace(basis.flat(step > 0 ? e : other), d);
      }
  }
  return faces;
}

void ghost_face_matrix(const ImmersedContext& context, const std::pair<int, int>& face,
                       std::vector<int>& cps, Eigen::MatrixXd& local) {
  const auto& basis = context.basis;
  const int dim = basis.dim();
  const auto& [flat, d] = face;
  const Element lower =
      context
          .cell_elements[static_cast<size_t>(context.cell_of_element[static_cast<size_t>(flat)])];
  Element upper = lower;
  ++upper[static_cast<size_t>(d)];
  const int p = basis.degree(d);
  const Eigen::Vector3d lo = basis.element_lo(lower), hi = basis.element_hi(lower);
  const double h = hi[d] - lo[d];
  const double factorial = std::tgamma(p + 1.0);
  const double factor = context.options->ghost_penalty *
                        (context.lame.lambda + 2 * context.lame.mu) * std::pow(h, 2 * p - 1) /
                        (factorial * factorial) * context.thickness;
  // The union of both elements' control points, and each one's place in it.
  std::vector<int> lower_cps, upper_cps;
  basis.control_points(lower, lower_cps);
  basis.control_points(upper, upper_cps);
  cps = lower_cps;
  std::unordered_map<int, int> place;
  for (size_t a = 0; a < cps.size(); ++a) place[cps[a]] = static_cast<int>(a);
  for (int cp : upper_cps)
    if (place.emplace(cp, static_cast<int>(cps.size())).second) cps.push_back(cp);
  const Eigen::Index m = static_cast<Eigen::Index>(cps.size());
  Eigen::MatrixXd scalar = Eigen::MatrixXd::Zero(m, m);
  // Gauss rule over the face (p + 1 points in each tangential direction).
  const nurbs::GaussRule g = nurbs::gauss_legendre(p + 1);
  const int n = static_cast<int>(g.points.size());
  const int count = dim == 2 ? n : n * n;
  Eigen::VectorXd lower_d, upper_d;
  for (int q = 0; q < count; ++q) {
    Eigen::Vector3d x = lo;
    x[d] = hi[d];
    double w = factor;
    int t = 0;
    for (int e = 0; e < dim; ++e) {
      if (e == d) continue;
      const size_t k = static_cast<size_t>(t == 0 ? q % n : q / n);
      x[e] = 0.5 * (lo[e] + hi[e]) + 0.5 * (hi[e] - lo[e]) * g.points[k];
      w *= 0.5 * (hi[e] - lo[e]) * g.weights[k];
      ++t;
    }
    // x is in grid coordinates (the element's bounds); the basis takes world points.
    basis.directional_derivative(lower, basis.to_world(x), d, p, lower_d);
    basis.directional_derivative(upper, basis.to_world(x), d, p, upper_d);
    Eigen::VectorXd jump = Eigen::VectorXd::Zero(m);
    for (size_t a = 0; a < lower_cps.size(); ++a)
      jump[place[lower_cps[a]]] += lower_d[static_cast<Eigen::Index>(a)];
    for (size_t a = 0; a < upper_cps.size(); ++a)
      jump[place[upper_cps[a]]] -= upper_d[static_cast<Eigen::Index>(a)];
    scalar.noalias() += w * jump * jump.transpose();
  }
  local.setZero(m * dim, m * dim);
  for (Eigen::Index b = 0; b < m; ++b)
    for (Eigen::Index a = 0; a < m; ++a)
      for (int c = 0; c < dim; ++c) local(a * dim + c, b * dim + c) = scalar(a, b);
}

int add_ghost_penalty(const ImmersedContext& context, ImmersedScatter& scatter) {
  const auto& faces = context.ghost;
  std::vector<int> cps;
  Eigen::MatrixXd local;
  for (const auto& face : faces) {
    ghost_face_matrix(context, face, cps, local);
    scatter.add_matrix(cps, local);
  }
  return static_cast<int>(faces.size());
}

}  // namespace isospring::analysis::detail
