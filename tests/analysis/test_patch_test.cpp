// Patch test: a linear displacement field must be reproduced to round-off on curved, distorted,
// rational patches (2D plane stress/strain and 3D), with Dirichlet data on some sides and the
// exact constant-stress tractions on the others.
#include <gtest/gtest.h>

#include <random>

#include "analysis_models.hpp"
#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/elasticity.hpp"
#include "isospring/analysis/post_processing.hpp"
#include "isospring/analysis/static_solver.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::analysis {
namespace {

using testing::quarter_ring;

// Perturbs the interior control points (and all weights) of a patch: the geometry is curved and
// irregular but stays valid.
nurbs::Patch distort(const nurbs::Patch& patch, double amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> shift(-amplitude, amplitude), weight(0.8, 1.25);
  std::vector<Eigen::Vector3d> points = patch.control_points();
  std::vector<double> weights = patch.weights();
  for (int i = 0; i < patch.num_points(); ++i) {
    const auto ijk = patch.net_position(i);
    bool interior = true;
    for (int d = 0; d < patch.param_dim(); ++d)
      interior = interior && ijk[static_cast<size_t>(d)] > 0 &&
                 ijk[static_cast<size_t>(d)] < patch.num_points(d) - 1;
    if (interior)
      for (int c = 0; c < (patch.physical_dim() == 2 ? 2 : 3); ++c)
        points[static_cast<size_t>(i)][c] += shift(rng);
    weights[static_cast<size_t>(i)] *= weight(rng);
  }
  return nurbs::Patch(patch.all_knots(), points, weights);
}

struct LinearField {
  Eigen::Vector3d a;
  Eigen::Matrix3d b;
  Eigen::Vector3d operator()(const Eigen::Vector3d& x) const { return a + b * x; }
};

// Supports with the exact field on the sides u0 and v0 (and w0), tractions sigma n on the rest.
Problem linear_field_problem(nurbs::Patch patch, Formulation formulation, const LinearField& u,
                             Volumetric volumetric = Volumetric::kDisplacement, double nu = 0.3) {
  Problem problem;
  problem.formulation = formulation;
  problem.volumetric = volumetric;
  problem.material = {200.0, nu, 1.0, 0.5};
  problem.patches.push_back(std::move(patch));
  const int dim = formulation == Formulation::kSolid ? 3 : 2;
  Eigen::Matrix3d grad = u.b;
  if (dim == 2) grad.row(2).setZero(), grad.col(2).setZero();
  Eigen::Matrix3d strain = 0.5 * (grad + grad.transpose());
  const Eigen::Matrix3d stress = stress_from_strain(strain, problem.material, formulation);
  LoadCase load;
  load.id = "tractions";
  for (int dir = 0; dir < dim; ++dir) {
    Support support;
    support.side = {0, dir, 0};
    support.fixed = {true, true, dim == 3};
    support.value_function = u;
    problem.supports.push_back(support);
    Traction traction;
    traction.side = {0, dir, 1};
    traction.function = [stress](const Eigen::Vector3d&,
                                 const Eigen::Vector3d& n) -> Eigen::Vector3d {
      return stress * n;
    };
    load.tractions.push_back(traction);
  }
  problem.load_cases.push_back(load);
  return problem;
}

double max_control_error(const Problem& problem, const StaticResult& result, const LinearField& u) {
  const int dim = problem.formulation == Formulation::kSolid ? 3 : 2;
  double error = 0.0;
  const auto& patch = problem.patches[0];
  for (int i = 0; i < patch.num_points(); ++i)
    for (int c = 0; c < dim; ++c)
      error = std::max(
          error, std::abs(result.load_cases[0].control_displacements[0][static_cast<size_t>(i)][c] -
                          u(patch.control_point(i))[c]));
  return error;
}

const LinearField kField2D{
    {1e-3, -2e-3, 0}, (Eigen::Matrix3d() << 1e-3, 2e-3, 0, -5e-4, 3e-3, 0, 0, 0, 0).finished()};

// With polynomial (non-rational) geometry grad(R_a) det J is a polynomial, so the default
// p + 1 Gauss points integrate the patch-test equations exactly, even on a distorted net.
TEST(PatchTest, PolynomialDistortedPatchIsExactWithDefaultQuadrature) {
  nurbs::Patch ring = nurbs::k_refine(quarter_ring(), {3, 3, 0}, {4, 5, 1});
  std::vector<Eigen::Vector3d> points = ring.control_points();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> shift(-0.04, 0.04);
  for (int i = 0; i < ring.num_points(); ++i) {
    const auto ij = ring.net_position(i);
    if (ij[0] > 0 && ij[0] < ring.num_points(0) - 1 && ij[1] > 0 && ij[1] < ring.num_points(1) - 1)
      points[static_cast<size_t>(i)] += Eigen::Vector3d(shift(rng), shift(rng), 0.0);
  }
  const Problem problem = linear_field_problem(nurbs::Patch(ring.all_knots(), points, {}),
                                               Formulation::kPlaneStress, kField2D);
  EXPECT_LT(max_control_error(problem, solve_static(problem), kField2D), 1e-12);
}

// Rational patches: Gauss quadrature integrates rational integrands only approximately, so the
// patch test holds to the quadrature error, which falls exponentially with the number of points
// (with the default p + 1 points the error here is ~1e-4 relative); 10 points reach round-off.
TEST(PatchTest, PlaneStressDistortedRationalRing) {
  nurbs::Patch ring = nurbs::k_refine(quarter_ring(), {3, 3, 0}, {4, 5, 1});
  Problem problem =
      linear_field_problem(distort(ring, 0.04, 1), Formulation::kPlaneStress, kField2D);
  problem.quadrature_points = 10;
  const StaticResult result = solve_static(problem);
  // Displacements are O(1e-2): round-off of a well-conditioned solve is ~1e-15 relative.
  EXPECT_LT(max_control_error(problem, result, kField2D), 1e-12);
  // Stress is the constant field everywhere.
  const FieldPoint field =
      evaluate_field(problem, result.load_cases[0].control_displacements, 0, {0.37, 0.61, 0});
  Eigen::Matrix3d grad = kField2D.b;
  const Eigen::Matrix3d stress =
      stress_from_strain(0.5 * (grad + grad.transpose()), problem.material, problem.formulation);
  EXPECT_LT((field.stress - stress).cwiseAbs().maxCoeff(), 1e-10 * stress.cwiseAbs().maxCoeff());
  EXPECT_NEAR(field.displacement.x(), kField2D(field.point).x(), 1e-12);
}

TEST(PatchTest, PlaneStrainDistortedRationalRingDegree2) {
  nurbs::Patch ring = nurbs::k_refine(quarter_ring(), {2, 2, 0}, {3, 4, 1});
  Problem problem =
      linear_field_problem(distort(ring, 0.05, 2), Formulation::kPlaneStrain, kField2D);
  problem.quadrature_points = 10;
  EXPECT_LT(max_control_error(problem, solve_static(problem), kField2D), 1e-12);
}

// The quarter ring extruded to z in [0, 0.7] with a tilt, degree 2 in every direction.
nurbs::Patch tilted_ring_volume() {
  const nurbs::Patch ring = quarter_ring();
  std::vector<Eigen::Vector3d> points;
  std::vector<double> weights;
  for (int k = 0; k < 2; ++k)
    for (int i = 0; i < ring.num_points(); ++i) {
      Eigen::Vector3d x = ring.control_point(i);
      x.z() = 0.7 * k + 0.1 * x.x() * k;
      points.push_back(x);
      weights.push_back(ring.weight(i));
    }
  nurbs::Patch volume({ring.knots(0), ring.knots(1), nurbs::KnotVector(1, {0, 0, 1, 1})}, points,
                      weights);
  return nurbs::k_refine(volume, {2, 2, 2}, {2, 3, 2});
}

// A general linear field for the 3D patch tests.
const LinearField kField3D{
    {1e-3, -2e-3, 5e-4},
    (Eigen::Matrix3d() << 1e-3, 2e-3, -1e-3, -5e-4, 3e-3, 2e-4, 7e-4, -3e-4, 1.5e-3).finished()};

TEST(PatchTest, SolidDistortedRationalVolume) {
  const nurbs::Patch volume = tilted_ring_volume();
  const LinearField& field = kField3D;
  Problem problem = linear_field_problem(distort(volume, 0.03, 3), Formulation::kSolid, field);
  problem.quadrature_points = 10;
  const StaticResult result = solve_static(problem);
  EXPECT_LT(max_control_error(problem, result, field), 1e-12);
  // Reactions balance the applied tractions: sum(K u - f) over supported DOFs = -sum(f).
  const DofMap dofs(problem);
  const Eigen::VectorXd force = assemble_load(problem, dofs, problem.load_cases[0]);
  Eigen::Vector3d applied = Eigen::Vector3d::Zero();
  for (int i = 0; i < dofs.num_dofs(); ++i) applied[i % 3] += force[i];
  EXPECT_GT(applied.norm(), 0.1);
  EXPECT_LT((result.load_cases[0].reaction_sum + applied).norm(), 1e-12 * applied.norm() * 1e3);
}

// B-bar keeps the patch test: the projection reproduces constants, so a linear field's
// projected dilatation is its own, and it preserves element integrals, so the virtual work of a
// constant stress is unchanged. Nearly incompressible, where any inconsistency would be amplified
// by kappa / mu ~ 1e4.
TEST(PatchTest, BbarPlaneStrainDistortedRationalRing) {
  // Degree 1 radially: its projection space is piecewise constant in that direction.
  for (int p : {1, 2, 3}) {
    nurbs::Patch ring = nurbs::k_refine(quarter_ring(), {p, std::max(p, 2), 0}, {3, 4, 1});
    Problem problem = linear_field_problem(distort(ring, 0.05, 2), Formulation::kPlaneStrain,
                                           kField2D, Volumetric::kBbar, 0.4999);
    // The rational integrands' quadrature error is amplified by kappa / mu: at p = 3 with 10
    // points both formulations miss by ~1e-9; 16 points reach round-off (measured 1e-14).
    problem.quadrature_points = 16;
    const StaticResult result = solve_static(problem);
    EXPECT_LT(max_control_error(problem, result, kField2D), 1e-10) << "p = " << p;
    const FieldPoint field =
        evaluate_field(problem, result.load_cases[0].control_displacements, 0, {0.37, 0.61, 0});
    Eigen::Matrix3d grad = kField2D.b;
    grad.row(2).setZero();
    grad.col(2).setZero();
    const Eigen::Matrix3d stress =
        stress_from_strain(0.5 * (grad + grad.transpose()), problem.material, problem.formulation);
    EXPECT_LT((field.stress - stress).cwiseAbs().maxCoeff(), 1e-8 * stress.cwiseAbs().maxCoeff())
        << "p = " << p;
  }
}

TEST(PatchTest, BbarSolidDistortedRationalVolume) {
  const nurbs::Patch volume = tilted_ring_volume();
  const LinearField& field = kField3D;
  Problem problem = linear_field_problem(distort(volume, 0.03, 3), Formulation::kSolid, field,
                                         Volumetric::kBbar, 0.4999);
  problem.quadrature_points = 10;
  EXPECT_LT(max_control_error(problem, solve_static(problem), field), 1e-10);
}

TEST(PatchTest, BbarRefusesPlaneStress) {
  Problem problem = linear_field_problem(nurbs::k_refine(quarter_ring(), {2, 2, 0}, {2, 2, 1}),
                                         Formulation::kPlaneStress, kField2D, Volumetric::kBbar);
  try {
    solve_static(problem);
    FAIL() << "plane stress with B-bar was accepted";
  } catch (const nurbs::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("plane stress does not lock"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace isospring::analysis
