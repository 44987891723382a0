// The Lame-split stiffness with spatial weights against closed forms (a constant strain in a box
// under a linear weight), against assemble_stiffness, and one pass for several weights against
// separate passes on one and on two threads.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/elasticity.hpp"
#include "isospring/analysis/lame_stiffness.hpp"
#include "isospring/analysis/thread_scope.hpp"

namespace isospring::analysis {
namespace {

constexpr double kLx = 2.0, kLy = 1.0, kLz = 0.5;

// A box [0, Lx] x [0, Ly] x [0, Lz], degree 2, four elements per direction (colours of several
// elements, so two threads share them), control points at the Greville abscissae: the map is
// affine, so a linear field is in the space (control values G x_a) and Gauss quadrature
// integrates polynomial weights exactly.
Problem box() {
  const nurbs::KnotVector knots(2, {0, 0, 0, 0.25, 0.5, 0.75, 1, 1, 1});
  const double greville[6] = {0.0, 0.125, 0.375, 0.625, 0.875, 1.0};
  std::vector<Eigen::Vector3d> points;
  for (int k = 0; k < 6; ++k)
    for (int j = 0; j < 6; ++j)
      for (int i = 0; i < 6; ++i)
        points.emplace_back(kLx * greville[i], kLy * greville[j], kLz * greville[k]);
  Problem problem;
  problem.formulation = Formulation::kSolid;
  problem.material = {70e9, 0.33, 2700.0, 1.0};
  problem.patches.emplace_back(std::vector<nurbs::KnotVector>{knots, knots, knots}, points);
  return problem;
}

TEST(LameStiffness, LinearWeightIntegratesAConstantStrainExactly) {
  const Problem problem = box();
  const DofMap dofs(problem);
  // w = 1 + x: int w dV = V (1 + Lx / 2).
  const auto parts = assemble_lame_stiffness(
      problem, dofs, {[](const Eigen::Vector3d& x) { return 1.0 + x.x(); }});
  ASSERT_EQ(parts.size(), 1u);
  const double weight_integral = kLx * kLy * kLz * (1.0 + kLx / 2.0);
  // u = G x with a non-symmetric gradient: u^T K_lambda u = tr(G)^2 int w and
  // u^T K_mu u = (|G|^2 + G : G^T) int w (= 2 eps : eps int w).
  Eigen::Matrix3d g;
  g << 0.3, -0.7, 0.2, 0.5, -0.1, 0.9, -0.4, 0.6, 0.8;
  Eigen::VectorXd u(dofs.num_dofs());
  const nurbs::Patch& patch = problem.patches[0];
  for (int a = 0; a < patch.num_points(); ++a)
    for (int i = 0; i < 3; ++i) u[dofs.dof(0, a, i)] = (g * patch.control_point(a))[i];
  const double trace = g.trace();
  const double shear = g.squaredNorm() + (g.array() * g.transpose().array()).sum();
  // Exact integration: agreement to rounding of sums over 64 elements x 27 points.
  EXPECT_NEAR(u.dot(parts[0].lambda_part * u), trace * trace * weight_integral,
              1e-12 * trace * trace * weight_integral);
  EXPECT_NEAR(u.dot(parts[0].mu_part * u), shear * weight_integral,
              1e-12 * shear * weight_integral);
  // Both parts are symmetric (full, not one triangle).
  for (const auto& m : {parts[0].lambda_part, parts[0].mu_part}) {
    const Eigen::SparseMatrix<double> transposed = m.transpose();
    EXPECT_LT((m - transposed).norm(), 1e-15 * m.norm());
  }
}

TEST(LameStiffness, UnweightedPartsReproduceTheStiffness) {
  const Problem problem = box();
  const DofMap dofs(problem);
  const auto parts = assemble_lame_stiffness(problem, dofs, {SpatialWeight()});
  const LameParameters lame = lame_parameters(problem.material, problem.formulation);
  const Eigen::SparseMatrix<double> upper = assemble_stiffness(problem, dofs);
  const Eigen::MatrixXd reference =
      Eigen::MatrixXd(Eigen::SparseMatrix<double>(upper.selfadjointView<Eigen::Upper>()));
  const Eigen::MatrixXd ours =
      Eigen::MatrixXd(lame.lambda * parts[0].lambda_part + lame.mu * parts[0].mu_part);
  // Same quadrature, different element code: agreement to rounding.
  EXPECT_LT((ours - reference).norm(), 1e-13 * reference.norm());
}

TEST(LameStiffness, OnePassForSeveralWeightsEqualsSeparatePassesOnAnyThreadCount) {
  const Problem problem = box();
  const DofMap dofs(problem);
  const std::vector<SpatialWeight> weights = {
      SpatialWeight(), [](const Eigen::Vector3d& x) { return x.y() - 0.5; },
      [](const Eigen::Vector3d& x) { return x.z() * x.z(); }};
  const auto together = assemble_lame_stiffness(problem, dofs, weights, 2);
  ASSERT_EQ(together.size(), weights.size());
  for (size_t k = 0; k < weights.size(); ++k) {
    for (int threads : {1, 2}) {
      const auto alone = assemble_lame_stiffness(problem, dofs, {weights[k]}, threads);
      // Elements of one colour share no node: every entry is summed in the same order whatever
      // the thread count, so the matrices are identical, not merely close.
      EXPECT_EQ(Eigen::MatrixXd(alone[0].lambda_part), Eigen::MatrixXd(together[k].lambda_part));
      EXPECT_EQ(Eigen::MatrixXd(alone[0].mu_part), Eigen::MatrixXd(together[k].mu_part));
    }
  }
  // A constant weight scales the parts.
  const auto doubled =
      assemble_lame_stiffness(problem, dofs, {[](const Eigen::Vector3d&) { return 2.0; }}, 1);
  EXPECT_LT(
      (Eigen::MatrixXd(doubled[0].mu_part) - 2.0 * Eigen::MatrixXd(together[0].mu_part)).norm(),
      1e-15 * Eigen::MatrixXd(doubled[0].mu_part).norm());
}

}  // namespace
}  // namespace isospring::analysis
