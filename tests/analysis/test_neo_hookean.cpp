// Compressible neo-Hookean (total Lagrangian): the tangent is the derivative of the internal
// force, rigid rotations carry no force, small loads recover linear elasticity to O(load^2), and a
// homogeneous uniaxial stretch (dead traction or prescribed end displacement) matches the closed
// form of W = mu/2 (I1bar - 3) + K/2 (J - 1)^2 solved here with scalar Newton iterations.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>

#include "analysis_models.hpp"
#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/neo_hookean.hpp"
#include "isospring/analysis/nonlinear_elasticity.hpp"
#include "isospring/analysis/static_solver.hpp"
#include "isospring/nurbs/error.hpp"
#include "nonlinear_test_models.hpp"

namespace isospring::analysis {
namespace {

using finite_strain_models::cantilever;
using finite_strain_models::curved_2d;
using finite_strain_models::curved_3d;
using finite_strain_models::random_field;

NonlinearOptions neo_hookean_options() {
  NonlinearOptions options;
  options.material = HyperelasticMaterial::kNeoHookean;
  return options;
}

void check_tangent(const Problem& problem, double scale) {
  const DofMap dofs(problem);
  const NeoHookeanAssembler assembler(problem, dofs);
  const NeoHookeanParameters moduli = neo_hookean_parameters(problem.material, problem.formulation);
  const int n = dofs.num_dofs();
  const Eigen::VectorXd u = random_field(n, scale, 7);
  Eigen::SparseMatrix<double> tangent;
  const Eigen::VectorXd force = assembler.internal_force(u, moduli, &tangent);
  ASSERT_TRUE(force.allFinite()) << "the random field inverts the material; use a smaller one";
  const Eigen::SparseMatrix<double> full = tangent.selfadjointView<Eigen::Upper>();
  for (unsigned seed : {11u, 12u, 13u}) {
    const Eigen::VectorXd v = random_field(n, 1.0, seed);
    // Central differences D(h) = K v + h^2/6 r'''[v,v,v] + O(h^4); Richardson
    // (4 D(h/2) - D(h)) / 3 leaves O(h^4) ~ 1e-16 and round-off ~1e-16 |r| / h ~ 1e-11.
    auto central = [&](double h) -> Eigen::VectorXd {
      return (assembler.internal_force(u + h * v, moduli) -
              assembler.internal_force(u - h * v, moduli)) /
             (2 * h);
    };
    const Eigen::VectorXd difference = (4.0 * central(0.5e-4) - central(1e-4)) / 3.0;
    const Eigen::VectorXd product = full * v;
    const double relative = (product - difference).norm() / product.norm();
    std::printf("neo-Hookean tangent vs central differences: %.2e relative\n", relative);
    EXPECT_LT(relative, 1e-8);
  }
  // At u = 0 the tangent is Hooke's law with lambda = K - 2 mu / 3 = E nu / ((1 + nu)(1 - 2 nu)):
  // the linear stiffness to round-off.
  Eigen::SparseMatrix<double> initial;
  const Eigen::VectorXd zero_force =
      assembler.internal_force(Eigen::VectorXd::Zero(n), moduli, &initial);
  EXPECT_LT(zero_force.norm(), 1e-12 * Eigen::MatrixXd(initial).norm());
  const Eigen::SparseMatrix<double> linear = assemble_stiffness(problem, dofs);
  EXPECT_LT((Eigen::MatrixXd(initial) - Eigen::MatrixXd(linear)).norm(),
            1e-12 * Eigen::MatrixXd(linear).norm());
}

TEST(NeoHookean, TangentIsTheDerivativeOfTheInternalForce2D) {
  check_tangent(curved_2d(), 0.05);
}

TEST(NeoHookean, TangentIsTheDerivativeOfTheInternalForce3D) {
  check_tangent(curved_3d(), 0.05);
}

// u = (Q - I) X at the control points is exactly the rigid rotation (F = Q, J = 1, I1 = 3):
// P = mu (Q - Q) + 0 = 0, while linear elasticity sees a strain and a force of order E |u|.
void check_rotation(const Problem& problem, const Eigen::Matrix3d& rotation) {
  const DofMap dofs(problem);
  const int dim = dofs.dofs_per_node();
  Eigen::VectorXd u(dofs.num_dofs());
  for (int node = 0; node < dofs.num_nodes(); ++node) {
    const Eigen::Vector3d x = dofs.node_positions()[static_cast<size_t>(node)];
    const Eigen::Vector3d d = rotation * x - x;
    for (int c = 0; c < dim; ++c) u[node * dim + c] = d[c];
  }
  const NeoHookeanAssembler assembler(problem, dofs);
  const NeoHookeanParameters moduli = neo_hookean_parameters(problem.material, problem.formulation);
  const Eigen::VectorXd linear =
      assemble_stiffness(problem, dofs).selfadjointView<Eigen::Upper>() * u;
  EXPECT_GT(linear.norm(), 1.0);
  EXPECT_LT(assembler.internal_force(u, moduli).norm(), 1e-10 * linear.norm());
}

TEST(NeoHookean, RigidRotationsCarryNoInternalForce) {
  check_rotation(curved_2d(), Eigen::AngleAxisd(1.1, Eigen::Vector3d::UnitZ()).toRotationMatrix());
  check_rotation(curved_3d(),
                 Eigen::AngleAxisd(0.9, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix());
}

TEST(NeoHookean, SmallLoadsRecoverLinearElasticityToSecondOrder) {
  // As for SVK: the nonlinear correction is first order in the deflection, so
  // |u_nl - u_lin| / |u_lin| halves with the load.
  std::vector<double> difference;
  for (double q : {4e-3, 2e-3, 1e-3}) {
    const Problem problem = cantilever(q);
    const Eigen::VectorXd linear = solve_static(problem).load_cases[0].displacement;
    const auto nonlinear = solve_static_nonlinear(problem, neo_hookean_options());
    difference.push_back((nonlinear[0].displacement - linear).norm() / linear.norm());
  }
  std::printf("neo-Hookean vs linear: %.3e %.3e %.3e\n", difference[0], difference[1],
              difference[2]);
  EXPECT_LT(difference[0], 1e-2);
  EXPECT_NEAR(difference[0] / difference[1], 2.0, 0.02);
  EXPECT_NEAR(difference[1] / difference[2], 2.0, 0.01);
}

// The homogeneous stretch F = diag(l1, l2, l2) (3D) or diag(l1, l2, 1) (plane strain) of this W.
struct Uniaxial {
  double shear, bulk;
  bool solid;
  // P_aa of F for the direction of stretch la (P = mu J^-2/3 (F - I1/3 F^-T) + K J (J - 1) F^-T is
  // diagonal).
  double stress(double la, double l1, double l2) const {
    const double J = solid ? l1 * l2 * l2 : l1 * l2;
    const double I1 = l1 * l1 + l2 * l2 + (solid ? l2 * l2 : 1.0);
    return shear * std::pow(J, -2.0 / 3.0) * (la - I1 / (3.0 * la)) + bulk * J * (J - 1.0) / la;
  }
  double p11(double l1, double l2) const { return stress(l1, l1, l2); }
  double p22(double l1, double l2) const { return stress(l2, l1, l2); }
  // The lateral stretch that frees the lateral faces (P_22 = 0): scalar Newton from 1 with a
  // central-difference derivative (the root is simple; the iteration converges to round-off).
  double lateral(double l1) const {
    double l2 = 1.0;
    for (int i = 0; i < 50; ++i) {
      const double h = 1e-6;
      const double slope = (p22(l1, l2 + h) - p22(l1, l2 - h)) / (2 * h);
      l2 -= p22(l1, l2) / slope;
    }
    return l2;
  }
  // The axial stretch under the dead traction P: Newton on P_11(l1, l2(l1)) = P.
  double axial(double P) const {
    double l1 = 1.0;
    for (int i = 0; i < 50; ++i) {
      const double h = 1e-6;
      auto f = [&](double l) { return p11(l, lateral(l)) - P; };
      l1 -= f(l1) / ((f(l1 + h) - f(l1 - h)) / (2 * h));
    }
    return l1;
  }
};

// Block [0, L] x [0, H] (x [0, W]) with symmetry supports on x = 0, y = 0 (z = 0); on x = L either
// the dead traction P or the prescribed displacement (l1 - 1) L.
Problem uniaxial_block(Formulation formulation, double nu) {
  const double E = 100.0, L = 2.0, H = 1.0, W = 0.5;
  Problem problem;
  problem.formulation = formulation;
  problem.material = {E, nu, 0.0, 1.0};
  nurbs::Patch block = testing::beam(L, H, 2, 3, 2);
  std::vector<Eigen::Vector3d> points;
  const bool solid = formulation == Formulation::kSolid;
  for (int k = 0; k < (solid ? 2 : 1); ++k)
    for (const auto& x : block.control_points())
      points.push_back(x + Eigen::Vector3d(0, H / 2, k * W));
  if (solid)
    block =
        nurbs::Patch({block.knots(0), block.knots(1), nurbs::KnotVector(1, {0, 0, 1, 1})}, points);
  else
    block = nurbs::Patch({block.knots(0), block.knots(1)}, points);
  problem.patches.push_back(block);
  for (int dir = 0; dir < (solid ? 3 : 2); ++dir) {
    Support symmetry;
    symmetry.side = {0, dir, 0};
    symmetry.symmetry = true;
    problem.supports.push_back(symmetry);
  }
  return problem;
}

// Largest |u - u_exact| over the control points for the homogeneous stretch (l1, l2).
double stretch_error(const Problem& problem, const NonlinearLoadCaseResult& result, double l1,
                     double l2) {
  const auto& points = problem.patches[0].control_points();
  const auto& u = result.control_displacements[0];
  double worst = 0.0;
  for (size_t i = 0; i < points.size(); ++i) {
    Eigen::Vector3d exact((l1 - 1) * points[i].x(), (l2 - 1) * points[i].y(), 0.0);
    if (problem.formulation == Formulation::kSolid) exact.z() = (l2 - 1) * points[i].z();
    worst = std::max(worst, (u[i] - exact).norm());
  }
  return worst;
}

void check_dead_traction(Formulation formulation, double nu, double P) {
  Problem problem = uniaxial_block(formulation, nu);
  LoadCase load;
  load.id = "pull";
  Traction t;
  t.side = {0, 0, 1};
  t.value = {P, 0, 0};
  load.tractions.push_back(t);
  problem.load_cases.push_back(load);
  const auto result = solve_static_nonlinear(problem, neo_hookean_options());
  const NeoHookeanParameters m = neo_hookean_parameters(problem.material, formulation);
  const Uniaxial law{m.shear, m.bulk, formulation == Formulation::kSolid};
  const double l1 = law.axial(P), l2 = law.lateral(l1);
  ASSERT_NEAR(law.p11(l1, l2), P, 1e-12 * std::abs(P));
  ASSERT_NEAR(law.p22(l1, l2), 0.0, 1e-12 * std::abs(P));
  const double error = stretch_error(problem, result[0], l1, l2);
  std::printf("neo-Hookean dead traction %g: l1 = %.6f, l2 = %.6f, error %.2e\n", P, l1, l2, error);
  EXPECT_LT(error, 1e-8 * std::abs(l1 - 1) * 2.0);
}

TEST(NeoHookean, UniaxialDeadTractionFollowsTheClosedForm) {
  // P = 0.3 E: l1 = 1.423 in 3D (42% stretch), 1.386 in plane strain.
  check_dead_traction(Formulation::kSolid, 0.3, 30.0);
  check_dead_traction(Formulation::kPlaneStrain, 0.3, 30.0);
  // Compression P = -0.3 E: l1 = 0.772. Neo-Hookean stiffens; the 1D SVK law
  // P = E l (l^2 - 1) / 2 has its limit point at l = 1 / sqrt(3), P = -0.19 E, before this load.
  check_dead_traction(Formulation::kSolid, 0.25, -30.0);
}

TEST(NeoHookean, UniaxialEndDisplacementGivesTheClosedFormReaction) {
  // 3D, nu = 0.3, 30% stretch by a prescribed end displacement: the reaction on x = L is
  // P_11 times the reference area H W.
  Problem problem = uniaxial_block(Formulation::kSolid, 0.3);
  const double l1 = 1.3, L = 2.0, area = 1.0 * 0.5;
  Support pull;
  pull.side = {0, 0, 1};
  pull.fixed = {true, false, false};
  pull.value = {(l1 - 1) * L, 0, 0};
  problem.supports.push_back(pull);
  LoadCase load;
  load.id = "stretch";
  problem.load_cases.push_back(load);
  const auto result = solve_static_nonlinear(problem, neo_hookean_options());
  const NeoHookeanParameters m = neo_hookean_parameters(problem.material, problem.formulation);
  const Uniaxial law{m.shear, m.bulk, true};
  const double l2 = law.lateral(l1);
  EXPECT_LT(stretch_error(problem, result[0], l1, l2), 1e-8 * (l1 - 1) * L) << "l2 = " << l2;
  // Reaction: the internal force summed over the x DOFs of the control points on x = L.
  const DofMap dofs(problem);
  const NeoHookeanAssembler assembler(problem, dofs);
  const Eigen::VectorXd internal = assembler.internal_force(result[0].displacement, m);
  double reaction = 0.0;
  const auto& points = problem.patches[0].control_points();
  for (size_t i = 0; i < points.size(); ++i)
    if (std::abs(points[i].x() - L) < 1e-12)
      reaction += internal[dofs.dof(0, static_cast<int>(i), 0)];
  const double exact = law.p11(l1, l2) * area;
  std::printf("neo-Hookean 30%% stretch: reaction %.12g, closed form %.12g\n", reaction, exact);
  EXPECT_NEAR(reaction, exact, 1e-8 * exact);
}

TEST(NeoHookean, ClampedBlockStretchedByItsEndConvergesInOneStep) {
  // A clamped block pulled 30 % at its other end: Newton's first correction carries the free DOFs
  // along with the driven side (through the tangent at rest), so one load step converges
  // quadratically. (Moving the driven side alone first squeezes the next elements: a degree-3
  // block of 8 x 2 x 2 elements, 2 x 0.5 x 0.5, then took 16 halved steps and 85 iterations.)
  Problem problem = uniaxial_block(Formulation::kSolid, 0.3);
  problem.patches[0] = nurbs::refine_uniform(nurbs::refine_uniform(problem.patches[0], 0, 3), 2, 2);
  problem.supports[0].symmetry = false;  // x = 0 clamped
  problem.supports[0].fixed = {true, true, true};
  Support pull;
  pull.side = {0, 0, 1};
  pull.fixed = {true, false, false};
  pull.value = {0.3 * 2.0, 0, 0};
  problem.supports.push_back(pull);
  LoadCase load;
  load.id = "stretch";
  problem.load_cases.push_back(load);
  for (HyperelasticMaterial material :
       {HyperelasticMaterial::kNeoHookean, HyperelasticMaterial::kSaintVenantKirchhoff}) {
    NonlinearOptions options;
    options.material = material;
    const auto result = solve_static_nonlinear(problem, options);
    std::printf("clamped block, 30%% end stretch: %d load steps, %d iterations\n",
                result[0].load_steps, result[0].iterations);
    EXPECT_EQ(result[0].load_steps, 1);
    EXPECT_LE(result[0].iterations, 6);
    EXPECT_LT(result[0].residual, 1e-10);
  }
}

TEST(NeoHookean, PlaneStressIsRefusedWithAReason) {
  Problem problem = cantilever(1e-3);
  problem.formulation = Formulation::kPlaneStress;
  try {
    solve_static_nonlinear(problem, neo_hookean_options());
    FAIL() << "expected an InputError";
  } catch (const nurbs::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("plane stress"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace isospring::analysis
