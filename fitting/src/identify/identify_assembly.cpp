// Side spring matrices (Gauss quadrature per knot span, as the analysis module); the Lame-split
// stiffness is analysis::assemble_lame_stiffness.
#include "isospring/fitting/identify_assembly.hpp"

#include <Eigen/Dense>
#include <utility>

#include "isospring/analysis/elasticity.hpp"
#include "isospring/analysis/sides.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/nurbs/quadrature.hpp"

namespace isospring::fitting {

namespace {

using Triplets = std::vector<Eigen::Triplet<double>>;

int points_per_direction(const analysis::Problem& problem, const nurbs::Patch& patch, int dir) {
  return problem.quadrature_points > 0 ? problem.quadrature_points : patch.degree(dir) + 1;
}

// Calls visit(u, weight) at every Gauss point of every element of the directions `dirs` (the
// others stay at `fixed`), with weight = product of the Gauss weights times the span lengths.
// `element_done` is called after the points of each element.
void for_each_gauss_point(const analysis::Problem& problem, const nurbs::Patch& patch,
                          const std::vector<int>& dirs, const nurbs::Param& fixed,
                          const std::function<void(const nurbs::Param&, double)>& visit,
                          const std::function<void()>& element_done) {
  std::vector<std::vector<std::pair<double, double>>> rules;  // per dir: (point, weight)
  std::vector<std::vector<std::pair<double, double>>> spans;  // per dir: (a, b)
  for (int d : dirs) {
    const nurbs::GaussRule rule = nurbs::gauss_legendre(points_per_direction(problem, patch, d));
    std::vector<std::pair<double, double>> r;
    for (size_t q = 0; q < rule.points.size(); ++q) r.emplace_back(rule.points[q], rule.weights[q]);
    rules.push_back(r);
    std::vector<std::pair<double, double>> s;
    for (int span : patch.knots(d).element_spans())
      s.emplace_back(patch.knots(d)[span], patch.knots(d)[span + 1]);
    spans.push_back(s);
  }
  const size_t nd = dirs.size();
  std::vector<size_t> e(nd, 0);
  while (true) {
    std::vector<size_t> q(nd, 0);
    while (true) {
      nurbs::Param u = fixed;
      double w = 1.0;
      for (size_t k = 0; k < nd; ++k) {
        const auto [a, b] = spans[k][e[k]];
        const auto [x, wx] = rules[k][q[k]];
        u[static_cast<size_t>(dirs[k])] = 0.5 * (a + b) + 0.5 * (b - a) * x;
        w *= 0.5 * (b - a) * wx;
      }
      visit(u, w);
      size_t k = 0;
      while (k < nd && ++q[k] == rules[k].size()) q[k++] = 0;
      if (k == nd) break;
    }
    element_done();
    size_t k = 0;
    while (k < nd && ++e[k] == spans[k].size()) e[k++] = 0;
    if (k == nd) break;
  }
}

Eigen::SparseMatrix<double> to_matrix(const Triplets& triplets, int size) {
  Eigen::SparseMatrix<double> m(size, size);
  m.setFromTriplets(triplets.begin(), triplets.end());
  return m;
}

}  // namespace

LameMatrices assemble_lame_stiffness(const analysis::Problem& problem, const analysis::DofMap& dofs,
                                     const analysis::SpatialWeight& weight) {
  return std::move(analysis::assemble_lame_stiffness(problem, dofs, {weight}).front());
}

SideSpringMatrices assemble_side_springs(const analysis::Problem& problem,
                                         const analysis::DofMap& dofs, const analysis::Side& side) {
  const int dim = dofs.dofs_per_node();
  const double thickness = analysis::thickness_factor(problem);
  const nurbs::Patch& patch = problem.patches[static_cast<size_t>(side.patch)];
  std::vector<int> dirs;
  for (int d = 0; d < patch.param_dim(); ++d)
    if (d != side.dir) dirs.push_back(d);
  nurbs::Param fixed{0.0, 0.0, 0.0};
  fixed[static_cast<size_t>(side.dir)] =
      side.end == 0 ? patch.param_min(side.dir) : patch.param_max(side.dir);
  Triplets normal, tangential;
  auto visit = [&](const nurbs::Param& u, double w) {
    const nurbs::RationalBasis basis = patch.basis(u, 0);
    const analysis::SideFrame frame =
        analysis::side_frame(patch.derivatives(u, 1).first, patch.param_dim(), side.dir, side.end);
    const Eigen::VectorXd n = frame.normal.head(dim);
    const Eigen::MatrixXd nn = n * n.transpose();
    const Eigen::MatrixXd tt = Eigen::MatrixXd::Identity(dim, dim) - nn;
    const double factor = w * frame.measure * thickness;
    const int count = static_cast<int>(basis.indices.size());
    for (int a = 0; a < count; ++a)
      for (int b = 0; b < count; ++b) {
        const double rr = factor * basis.values[a] * basis.values[b];
        if (rr == 0.0) continue;
        for (int i = 0; i < dim; ++i)
          for (int j = 0; j < dim; ++j) {
            const int r = dofs.dof(side.patch, basis.indices[static_cast<size_t>(a)], i);
            const int c = dofs.dof(side.patch, basis.indices[static_cast<size_t>(b)], j);
            normal.emplace_back(r, c, rr * nn(i, j));
            tangential.emplace_back(r, c, rr * tt(i, j));
          }
      }
  };
  for_each_gauss_point(problem, patch, dirs, fixed, visit, [] {});
  return {to_matrix(normal, dofs.num_dofs()), to_matrix(tangential, dofs.num_dofs())};
}

}  // namespace isospring::fitting
