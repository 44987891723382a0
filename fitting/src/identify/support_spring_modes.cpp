// Split of a support's normal springs into axial, rocking and the rest (support_spring_modes.hpp):
// projections in the springs' own metric onto rigid fields of the side, which NURBS represent
// exactly (x = sum R_a P_a, so u_a = A P_a + b is the field u(x) = A x + b).
#include "isospring/fitting/support_spring_modes.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <vector>

#include "isospring/analysis/sides.hpp"

namespace isospring::fitting {

namespace {

using Triplets = std::vector<Eigen::Triplet<double>>;

// DOF vector of the field u(x) = field(x) on the side's control points (zero elsewhere: the
// springs of the side see only those).
template <typename Field>
Eigen::VectorXd side_field(const nurbs::Patch& patch, const analysis::DofMap& dofs,
                           const analysis::Side& side, const std::vector<int>& points,
                           Field field) {
  Eigen::VectorXd v = Eigen::VectorXd::Zero(dofs.num_dofs());
  const int dim = dofs.dofs_per_node();
  for (int a : points) {
    const Eigen::Vector3d u = field(patch.control_point(a));
    for (int c = 0; c < dim; ++c) v[dofs.dof(side.patch, a, c)] = u[c];
  }
  return v;
}

// Adds y y^T / g to `out` (the rank-one projection term of a direction v with y = N v, g = v^T y).
void add_rank_one(const Eigen::VectorXd& y, double g, Triplets& out) {
  std::vector<int> rows;
  for (Eigen::Index i = 0; i < y.size(); ++i)
    if (y[i] != 0.0) rows.push_back(static_cast<int>(i));
  for (int r : rows)
    for (int c : rows) out.emplace_back(r, c, y[r] * y[c] / g);
}

}  // namespace

NormalSpringSplit split_normal_springs(const analysis::Problem& problem,
                                       const analysis::DofMap& dofs, const analysis::Side& side,
                                       const Eigen::SparseMatrix<double>& normal) {
  const nurbs::Patch& patch = problem.patches[static_cast<size_t>(side.patch)];
  const int dim = dofs.dofs_per_node();
  const std::vector<int> points = analysis::side_control_points(patch, side.dir, side.end);
  // Mean normal: the translation the normal springs resist most (for a flat side, its normal;
  // the Gram matrix is then A n n^T).
  std::vector<Eigen::VectorXd> translations;
  for (int c = 0; c < dim; ++c)
    translations.push_back(side_field(patch, dofs, side, points, [c](const Eigen::Vector3d&) {
      return Eigen::Vector3d::Unit(c);
    }));
  Eigen::MatrixXd gram(dim, dim);
  for (int i = 0; i < dim; ++i)
    for (int j = 0; j < dim; ++j) gram(i, j) = translations[i].dot(normal * translations[j]);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(gram);
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  n.head(dim) = eig.eigenvectors().col(dim - 1);
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (int a : points) centre += patch.control_point(a);
  centre /= static_cast<double>(points.size());
  // Rotation axes: the side's in-plane directions (3D), the out-of-plane axis (2D).
  std::vector<Eigen::Vector3d> axes;
  if (dim == 2) {
    axes.push_back(Eigen::Vector3d::UnitZ());
  } else {
    const Eigen::Vector3d a1 = n.unitOrthogonal();
    axes.push_back(a1);
    axes.push_back(n.cross(a1));
  }
  // N-orthogonal directions: the translation along n, then the rotations (Gram-Schmidt). A
  // rotation the normal springs do not see (a side with no extent across that axis) is skipped.
  std::vector<Eigen::VectorXd> basis{
      side_field(patch, dofs, side, points, [&n](const Eigen::Vector3d&) { return n; })};
  for (const Eigen::Vector3d& axis : axes)
    basis.push_back(side_field(patch, dofs, side, points, [&](const Eigen::Vector3d& x) {
      return Eigen::Vector3d(axis.cross(x - centre));
    }));
  Triplets axial, rocking;
  std::vector<Eigen::VectorXd> done_v, done_y;
  std::vector<double> done_g;
  for (size_t k = 0; k < basis.size(); ++k) {
    Eigen::VectorXd v = basis[k];
    const double before = v.dot(normal * v);
    for (size_t j = 0; j < done_v.size(); ++j) v -= (done_y[j].dot(v) / done_g[j]) * done_v[j];
    const Eigen::VectorXd y = normal * v;
    const double g = v.dot(y);
    if (!(g > 1e-10 * before) || !(before > 0.0)) continue;
    add_rank_one(y, g, k == 0 ? axial : rocking);
    done_v.push_back(v);
    done_y.push_back(y);
    done_g.push_back(g);
  }
  NormalSpringSplit split;
  const auto size = static_cast<Eigen::Index>(dofs.num_dofs());
  split.axial.resize(size, size);
  split.axial.setFromTriplets(axial.begin(), axial.end());
  split.rocking.resize(size, size);
  split.rocking.setFromTriplets(rocking.begin(), rocking.end());
  split.rest = normal - split.axial - split.rocking;
  return split;
}

}  // namespace isospring::fitting
