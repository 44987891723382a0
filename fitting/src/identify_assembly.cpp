// Element loops for the Lame-split stiffness and side spring matrices (Gauss quadrature per
// knot span, as the analysis module, so the matrices agree with analysis::assemble_stiffness).
#include "isospring/fitting/identify_assembly.hpp"

#include <Eigen/Dense>

#include "isospring/analysis/elasticity.hpp"
#include "isospring/analysis/sides.hpp"
#include "isospring/analysis/thread_scope.hpp"
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
                                     const std::function<double(const Eigen::Vector3d&)>& weight) {
  // One thread: the element loop is serial, and Eigen would otherwise split each element's
  // n x n products (64 x 64 x 64 at degree 3 in 3D) over OpenMP threads that spin-wait for each
  // other (measured on the suite's tube, 11,025 DOFs: 55 % of the CPU time of identify went to
  // that spinning on a loaded 2-core machine).
  const analysis::ThreadScope serial(1);
  const int dim = dofs.dofs_per_node();
  const double thickness = analysis::thickness_factor(problem);
  Triplets lambda_triplets, mu_triplets;
  for (size_t p = 0; p < problem.patches.size(); ++p) {
    const nurbs::Patch& patch = problem.patches[p];
    std::vector<int> dirs(static_cast<size_t>(patch.param_dim()));
    for (int d = 0; d < patch.param_dim(); ++d) dirs[static_cast<size_t>(d)] = d;
    // Per element, the basis gradients at its Gauss points are collected column-wise per
    // component, grad_i = [dR/dx_i at q1, q2, ...] (n x points), with the weighted copies
    // weighted_i = grad_i diag(w_q det_q t weight(x_q)). The element blocks are then products:
    //   lambda part (i, j) = weighted_i grad_j^T,
    //   mu part (i, j)     = delta_ij sum_k weighted_k grad_k^T + weighted_j grad_i^T,
    // n x n matrix products instead of a loop over point x a x b x i x j (4 x faster at degree 3
    // in 3D, and the scattered entries are the same).
    std::vector<int> element_dofs;  // a * dim + i -> global DOF
    std::vector<Eigen::VectorXd> point_grads[3], point_weighted[3];
    auto flush = [&] {
      const auto n = static_cast<Eigen::Index>(element_dofs.size() / static_cast<size_t>(dim));
      const auto points = static_cast<Eigen::Index>(point_grads[0].size());
      Eigen::MatrixXd grad[3], weighted[3];
      for (int i = 0; i < dim; ++i) {
        grad[i].resize(n, points);
        weighted[i].resize(n, points);
        for (Eigen::Index q = 0; q < points; ++q) {
          grad[i].col(q) = point_grads[i][static_cast<size_t>(q)];
          weighted[i].col(q) = point_weighted[i][static_cast<size_t>(q)];
        }
        point_grads[i].clear();
        point_weighted[i].clear();
      }
      // products[i][j] = weighted_i grad_j^T: the lambda part's block (i, j) and, transposed in
      // the component pair, the mu part's block (j, i) (each product is needed twice).
      Eigen::MatrixXd products[3][3];
      for (int i = 0; i < dim; ++i)
        for (int j = 0; j < dim; ++j) products[i][j].noalias() = weighted[i] * grad[j].transpose();
      Eigen::MatrixXd trace = Eigen::MatrixXd::Zero(n, n);
      for (int k = 0; k < dim; ++k) trace += products[k][k];
      Eigen::MatrixXd mu_block(n, n);
      for (int i = 0; i < dim; ++i)
        for (int j = 0; j < dim; ++j) {
          const Eigen::MatrixXd& lambda_block = products[i][j];
          mu_block = products[j][i];
          if (i == j) mu_block += trace;
          for (Eigen::Index a = 0; a < n; ++a)
            for (Eigen::Index b = 0; b < n; ++b) {
              const int r = element_dofs[static_cast<size_t>(a * dim + i)];
              const int c = element_dofs[static_cast<size_t>(b * dim + j)];
              lambda_triplets.emplace_back(r, c, lambda_block(a, b));
              mu_triplets.emplace_back(r, c, mu_block(a, b));
            }
        }
      element_dofs.clear();
    };
    auto visit = [&](const nurbs::Param& u, double w) {
      const nurbs::RationalBasis basis = patch.basis(u, 1);
      const Eigen::Matrix3d jac3 = patch.derivatives(u, 1).first;
      const Eigen::MatrixXd jac = jac3.topLeftCorner(dim, dim);
      const double det = jac.determinant();
      if (!(det > 0.0))
        throw nurbs::InputError("patch " + std::to_string(p) +
                                ": the Jacobian determinant is not positive at a quadrature "
                                "point; fix the parametrisation (inverted or degenerate)");
      const Eigen::MatrixXd grad = basis.first.leftCols(dim) * jac.inverse();  // n x dim
      const int n = static_cast<int>(basis.indices.size());
      if (element_dofs.empty()) {
        element_dofs.resize(static_cast<size_t>(n * dim));
        for (int a = 0; a < n; ++a)
          for (int i = 0; i < dim; ++i)
            element_dofs[static_cast<size_t>(a * dim + i)] =
                dofs.dof(static_cast<int>(p), basis.indices[static_cast<size_t>(a)], i);
      }
      // All Gauss points of one element share the same basis support (same indices order).
      Eigen::Vector3d x = Eigen::Vector3d::Zero();
      for (int a = 0; a < n; ++a)
        x += basis.values[a] * patch.control_point(basis.indices[static_cast<size_t>(a)]);
      const double factor = w * det * thickness * (weight ? weight(x) : 1.0);
      for (int i = 0; i < dim; ++i) {
        point_grads[i].push_back(grad.col(i));
        point_weighted[i].push_back(factor * grad.col(i));
      }
    };
    for_each_gauss_point(problem, patch, dirs, {0.0, 0.0, 0.0}, visit, flush);
  }
  return {to_matrix(lambda_triplets, dofs.num_dofs()), to_matrix(mu_triplets, dofs.num_dofs())};
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
