// Total Lagrangian St. Venant-Kirchhoff: the tangent is the derivative of the internal force, the
// force vanishes for rigid rotations, small loads recover linear elasticity to O(load^2), and a
// uniaxial stretch under a dead end traction follows the closed-form cubic.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "analysis_models.hpp"
#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/nonlinear_elasticity.hpp"
#include "isospring/analysis/static_solver.hpp"
#include "nonlinear_test_models.hpp"

namespace isospring::analysis {
namespace {

using finite_strain_models::cantilever;
using finite_strain_models::curved_2d;
using finite_strain_models::curved_3d;
using finite_strain_models::random_field;

void check_tangent(const Problem& problem) {
  const DofMap dofs(problem);
  const SvkAssembler svk(problem, dofs);
  const LameParameters lame = lame_parameters(problem.material, problem.formulation);
  const int n = dofs.num_dofs();
  const Eigen::VectorXd u = random_field(n, 0.1, 7);
  Eigen::SparseMatrix<double> tangent;
  svk.internal_force(u, lame, &tangent);
  const Eigen::SparseMatrix<double> full = tangent.selfadjointView<Eigen::Upper>();
  for (unsigned seed : {11u, 12u, 13u}) {
    const Eigen::VectorXd v = random_field(n, 1.0, seed);
    // The force is a cubic polynomial in u, so the central difference is exactly
    // D(h) = K v + h^2/6 r'''[v,v,v]; Richardson (4 D(h/2) - D(h)) / 3 removes the h^2 term and
    // leaves round-off, ~1e-16 |r| / h ~ 1e-11 relative for h = 1e-4.
    auto central = [&](double h) -> Eigen::VectorXd {
      return (svk.internal_force(u + h * v, lame) - svk.internal_force(u - h * v, lame)) / (2 * h);
    };
    const Eigen::VectorXd difference = (4.0 * central(0.5e-4) - central(1e-4)) / 3.0;
    const Eigen::VectorXd product = full * v;
    EXPECT_LT((product - difference).norm(), 1e-9 * product.norm());  // measured 2.4e-12
  }
  // At u = 0 the tangent is the linear stiffness (same quadrature): identical to round-off.
  Eigen::SparseMatrix<double> initial;
  const Eigen::VectorXd zero_force = svk.internal_force(Eigen::VectorXd::Zero(n), lame, &initial);
  EXPECT_EQ(zero_force.norm(), 0.0);
  const Eigen::SparseMatrix<double> linear = assemble_stiffness(problem, dofs);
  EXPECT_LT((Eigen::MatrixXd(initial) - Eigen::MatrixXd(linear)).norm(),
            1e-12 * Eigen::MatrixXd(linear).norm());
}

TEST(NonlinearElasticity, TangentIsTheDerivativeOfTheInternalForce2D) {
  check_tangent(curved_2d());
}

TEST(NonlinearElasticity, TangentIsTheDerivativeOfTheInternalForce3D) {
  check_tangent(curved_3d());
}

// u = (Q - I) X at the control points is exactly the rigid rotation (NURBS reproduce linear
// fields), so F = Q, E = 0 and the SVK force vanishes; linear elasticity sees a strain
// (Q + Q^T)/2 - I and a force of order E |u|.
void check_rotation(const Problem& problem, const Eigen::Matrix3d& rotation) {
  const DofMap dofs(problem);
  const int dim = dofs.dofs_per_node();
  Eigen::VectorXd u(dofs.num_dofs());
  for (int node = 0; node < dofs.num_nodes(); ++node) {
    const Eigen::Vector3d x = dofs.node_positions()[static_cast<size_t>(node)];
    const Eigen::Vector3d d = rotation * x - x;
    for (int c = 0; c < dim; ++c) u[node * dim + c] = d[c];
  }
  const SvkAssembler svk(problem, dofs);
  const LameParameters lame = lame_parameters(problem.material, problem.formulation);
  const Eigen::VectorXd linear =
      assemble_stiffness(problem, dofs).selfadjointView<Eigen::Upper>() * u;
  EXPECT_GT(linear.norm(), 1.0);  // the linear model is not rotation invariant
  EXPECT_LT(svk.internal_force(u, lame).norm(), 1e-10 * linear.norm());  // measured 5e-16
}

TEST(NonlinearElasticity, RigidRotationsCarryNoInternalForce) {
  check_rotation(curved_2d(), Eigen::AngleAxisd(1.1, Eigen::Vector3d::UnitZ()).toRotationMatrix());
  check_rotation(curved_3d(),
                 Eigen::AngleAxisd(0.9, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix());
}

TEST(NonlinearElasticity, SmallLoadsRecoverLinearElasticityToSecondOrder) {
  // Linear tip deflection 4 q L^3 / (E D^3) (1 - nu^2) ~ 3.6 q: q = 1e-3 is a deflection of
  // ~4e-4 of the length. The nonlinear correction (axial shortening ~ deflection^2, stiffening
  // ~ deflection^3) makes |u_nl - u_lin| / |u_lin| proportional to q.
  std::vector<double> difference;
  for (double q : {4e-3, 2e-3, 1e-3}) {
    const Problem problem = cantilever(q);
    const Eigen::VectorXd linear = solve_static(problem).load_cases[0].displacement;
    const auto nonlinear = solve_static_nonlinear(problem);
    difference.push_back((nonlinear[0].displacement - linear).norm() / linear.norm());
  }
  EXPECT_LT(difference[0], 1e-2);
  // Halving the load halves the relative difference: ratios 2 up to the O(q^2) next term.
  EXPECT_NEAR(difference[0] / difference[1], 2.0, 0.02);
  EXPECT_NEAR(difference[1] / difference[2], 2.0, 0.01);
}

TEST(NonlinearElasticity, LargeTipLoadConvergesQuadratically) {
  // q = 0.5: linear tip deflection 3.64 q = 1.82, 18% of the length.
  const auto result = solve_static_nonlinear(cantilever(0.5));
  const auto linear = solve_static(cantilever(0.5));
  ASSERT_EQ(result.size(), 1u);
  EXPECT_EQ(result[0].load_steps, 1);
  EXPECT_LE(result[0].iterations, 8);  // Newton from zero, quadratic near the solution
  EXPECT_LT(result[0].residual, 1e-10);
  // Tension stiffening and the rotated load path: the nonlinear tip moves less than linear.
  const double tip_linear = linear.load_cases[0].max_displacement;
  EXPECT_LT(result[0].max_displacement, tip_linear);
  EXPECT_GT(result[0].max_displacement, 0.9 * tip_linear);
}

// Block [0, L] x [0, H] (x [0, W]) with symmetry supports on the x = 0, y = 0 (z = 0) faces and a
// dead traction P (first Piola, per reference area) on x = L. The exact solution is the
// homogeneous stretch F = diag(l1, l2, l2) with S_22 = 0: E_22 = -nu E_11 and
// P = E l1 (l1^2 - 1) / 2 (3D, and 2D plane stress with lambda*; nu = 0 for plane strain).
double stretch_for_load(double P, double E) {
  // Newton on l (l^2 - 1) E / 2 = P from l = 1 (monotone convex for l >= 1).
  double l = 1.0;
  for (int i = 0; i < 60; ++i) l -= (0.5 * E * l * (l * l - 1) - P) / (0.5 * E * (3 * l * l - 1));
  return l;
}

void check_uniaxial(Formulation formulation, double nu, double P) {
  const double E = 100.0, L = 2.0, H = 1.0, W = 0.5;
  Problem problem;
  problem.formulation = formulation;
  problem.material = {E, nu, 0.0, 1.0};
  nurbs::Patch block = testing::beam(L, H, 2, 3, 2);
  if (formulation == Formulation::kSolid) {
    std::vector<Eigen::Vector3d> points;
    for (int k = 0; k < 2; ++k)
      for (const auto& x : block.control_points())
        points.push_back(x + Eigen::Vector3d(0, H / 2, k * W));
    block =
        nurbs::Patch({block.knots(0), block.knots(1), nurbs::KnotVector(1, {0, 0, 1, 1})}, points);
  } else {
    std::vector<Eigen::Vector3d> points;
    for (const auto& x : block.control_points()) points.push_back(x + Eigen::Vector3d(0, H / 2, 0));
    block = nurbs::Patch({block.knots(0), block.knots(1)}, points);
  }
  problem.patches.push_back(block);
  const int dim = formulation == Formulation::kSolid ? 3 : 2;
  for (int dir = 0; dir < dim; ++dir) {
    Support symmetry;
    symmetry.side = {0, dir, 0};
    symmetry.symmetry = true;
    problem.supports.push_back(symmetry);
  }
  LoadCase load;
  load.id = "pull";
  Traction t;
  t.side = {0, 0, 1};
  t.value = {P, 0, 0};
  load.tractions.push_back(t);
  problem.load_cases.push_back(load);
  const auto result = solve_static_nonlinear(problem);
  const double l1 = stretch_for_load(P, E);
  ASSERT_NEAR(0.5 * E * l1 * (l1 * l1 - 1), P, 1e-12 * std::abs(P));
  const double effective_nu = formulation == Formulation::kPlaneStrain ? 0.0 : nu;
  const double l2 = std::sqrt(1.0 - effective_nu * (l1 * l1 - 1.0));
  // Every control point moves with the homogeneous field (the exact solution is linear in X).
  const auto& points = problem.patches[0].control_points();
  const auto& u = result[0].control_displacements[0];
  double worst = 0.0;
  for (size_t i = 0; i < points.size(); ++i) {
    Eigen::Vector3d exact((l1 - 1) * points[i].x(), (l2 - 1) * points[i].y(), 0.0);
    if (dim == 3) exact.z() = (l2 - 1) * points[i].z();
    worst = std::max(worst, (u[i] - exact).norm());
  }
  EXPECT_LT(worst, 1e-8 * std::abs(l1 - 1) * L) << "l1 = " << l1 << ", l2 = " << l2;
}

TEST(NonlinearElasticity, UniaxialStretchFollowsTheClosedFormCubic) {
  // P = 0.3 E: l1 = 1.2455 (25% stretch; linear elasticity would give 30%).
  check_uniaxial(Formulation::kPlaneStrain, 0.0, 30.0);
  check_uniaxial(Formulation::kPlaneStress, 0.3, 30.0);
  check_uniaxial(Formulation::kSolid, 0.3, 30.0);
  // Compression (P = -0.15 E, l1 = 0.8375): the tangent stays definite, Newton converges too.
  check_uniaxial(Formulation::kSolid, 0.25, -15.0);
}

TEST(NonlinearElasticity, NewtonFailureIsARuntimeError) {
  NonlinearOptions options;
  options.max_iterations = 1;
  options.max_step_halvings = 1;
  try {
    solve_static_nonlinear(cantilever(0.5), options);
    FAIL() << "expected a runtime_error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("did not converge"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("\"tip\""), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace isospring::analysis
