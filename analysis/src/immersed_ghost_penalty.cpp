// Ghost penalty: gamma (lambda + 2 mu) h^(2p-1) int_F [d^p u/dn^p].[d^p v/dn^p] on the grid faces
// of cut cells shared with another active cell (why: immersed.hpp).
#include <cmath>
#include <set>
#include <unordered_map>
#include <utility>

#include "immersed_kernels.hpp"
#include "isospring/geometry/immersed_domain.hpp"
#include "isospring/nurbs/quadrature.hpp"

namespace isospring::analysis::detail {

namespace {

// Faces (lower element, direction) of cut cells with an active neighbour across them.
std::set<std::pair<int, int>> ghost_faces(const ImmersedContext& context) {
  const auto& basis = context.basis;
  std::set<std::pair<int, int>> faces;
  for (size_t c = 0; c < context.domain->cells.size(); ++c) {
    if (context.domain->cells[c].kind != geometry::CellKind::kCut) continue;
    const Element& e = context.cell_elements[c];
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

}  // namespace

int add_ghost_penalty(const ImmersedContext& context, ImmersedScatter& scatter) {
  const auto& basis = context.basis;
  const int dim = basis.dim();
  const double modulus = context.lame.lambda + 2 * context.lame.mu;
  const auto faces = ghost_faces(context);
  std::vector<int> lower_cps, upper_cps, cps;
  Eigen::VectorXd lower_d, upper_d;
  for (const auto& [flat, d] : faces) {
    const Element lower =
        context
            .cell_elements[static_cast<size_t>(context.cell_of_element[static_cast<size_t>(flat)])];
    Element upper = lower;
    ++upper[static_cast<size_t>(d)];
    const int p = basis.degree(d);
    const Eigen::Vector3d lo = basis.element_lo(lower), hi = basis.element_hi(lower);
    const double h = hi[d] - lo[d];
    const double factor =
        context.options->ghost_penalty * modulus * std::pow(h, 2 * p - 1) * context.thickness;
    // The union of both elements' control points, and each one's place in it.
    basis.control_points(lower, lower_cps);
    basis.control_points(upper, upper_cps);
    cps = lower_cps;
    std::unordered_map<int, int> place;
    for (size_t a = 0; a < cps.size(); ++a) place[cps[a]] = static_cast<int>(a);
    for (int cp : upper_cps)
      if (place.emplace(cp, static_cast<int>(cps.size())).second) cps.push_back(cp);
    Eigen::MatrixXd scalar = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(cps.size()),
                                                   static_cast<Eigen::Index>(cps.size()));
    // Gauss rule over the face (p + 1 points in each tangential direction).
    const nurbs::GaussRule g = nurbs::gauss_legendre(p + 1);
    const int n = static_cast<int>(g.points.size());
    const int tangential = dim - 1;
    const int count = tangential == 1 ? n : n * n;
    for (int q = 0; q < count; ++q) {
      Eigen::Vector3d x = lo;
      x[d] = hi[d];
      double w = factor;
      int t = 0;
      for (int e = 0; e < dim; ++e) {
        if (e == d) continue;
        const size_t m = static_cast<size_t>(t == 0 ? q % n : q / n);
        x[e] = 0.5 * (lo[e] + hi[e]) + 0.5 * (hi[e] - lo[e]) * g.points[m];
        w *= 0.5 * (hi[e] - lo[e]) * g.weights[m];
        ++t;
      }
      basis.directional_derivative(lower, x, d, p, lower_d);
      basis.directional_derivative(upper, x, d, p, upper_d);
      Eigen::VectorXd jump = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(cps.size()));
      for (size_t a = 0; a < lower_cps.size(); ++a)
        jump[place[lower_cps[a]]] += lower_d[static_cast<Eigen::Index>(a)];
      for (size_t a = 0; a < upper_cps.size(); ++a)
        jump[place[upper_cps[a]]] -= upper_d[static_cast<Eigen::Index>(a)];
      scalar.noalias() += w * jump * jump.transpose();
    }
    Eigen::MatrixXd local = Eigen::MatrixXd::Zero(scalar.rows() * dim, scalar.cols() * dim);
    for (Eigen::Index b = 0; b < scalar.cols(); ++b)
      for (Eigen::Index a = 0; a < scalar.rows(); ++a)
        for (int c = 0; c < dim; ++c) local(a * dim + c, b * dim + c) = scalar(a, b);
    scatter.add_matrix(cps, local);
  }
  return static_cast<int>(faces.size());
}

}  // namespace isospring::analysis::detail
