// kAuto's rule (choose_solver) and what it reads from a problem (solver_problem_traits).
// Independent checks: the aspect ratio of a k-refined box against the variances of the Greville
// abscissae of its knot vectors (the control points of an affine map sit there), its invariance
// under a rotation; the rule's monotonicity in load cases, Poisson ratio and slenderness; on
// small versions of the benchmark problems of bench/bench_solvers.cpp (with the full size's free
// DOFs), the solver that was fastest there.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "analysis_models.hpp"
#include "isospring/analysis/constraints.hpp"
#include "isospring/analysis/static_solver.hpp"

namespace isospring::analysis {
namespace {
using Method = SolverOptions::Method;

nurbs::Patch box(Eigen::Vector3d size, std::array<int, 3> elements, int degree = 2) {
  const nurbs::KnotVector linear(1, {0, 0, 1, 1});
  std::vector<Eigen::Vector3d> points;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) points.emplace_back(size.x() * i, size.y() * j, size.z() * k);
  return nurbs::k_refine(nurbs::Patch({linear, linear, linear}, points), {degree, degree, degree},
                         {elements[0], elements[1], elements[2]});
}

// A box clamped at x = 0 under its own weight, `cases` load cases.
Problem clamped(nurbs::Patch patch, double nu, int cases = 1) {
  Problem problem;
  problem.formulation = Formulation::kSolid;
  problem.material = {210e9, nu, 7800, 1.0};
  problem.patches.push_back(std::move(patch));
  Support clamp;
  clamp.side = {0, 0, 0};
  clamp.fixed = {true, true, true};
  problem.supports.push_back(clamp);
  for (int c = 0; c < cases; ++c) {
    LoadCase load;
    load.id = "g" + std::to_string(c);
    load.gravity = {0, 0, -9.81};
    problem.load_cases.push_back(load);
  }
  return problem;
}

SolverTraits traits_of(const Problem& problem) {
  const SupportedProblem supported = number_and_support(problem);
  return solver_problem_traits(problem, supported.dofs, supported.constraints);
}

// Variance of the Greville abscissae (means of `degree` consecutive inner knots).
double greville_variance(const nurbs::KnotVector& knots) {
  const int p = knots.degree(), n = knots.num_basis();
  std::vector<double> g(static_cast<size_t>(n), 0.0);
  double mean = 0;
  for (int i = 0; i < n; ++i) {
    for (int k = 1; k <= p; ++k) g[static_cast<size_t>(i)] += knots[i + k] / p;
    mean += g[static_cast<size_t>(i)] / n;
  }
  double variance = 0;
  for (double x : g) variance += (x - mean) * (x - mean) / n;
  return variance;
}

TEST(SolverChoice, TraitsOfASlenderBoxAreItsExtentsAndMaterial) {
  const nurbs::Patch beam = box({50, 1, 1}, {40, 3, 3});
  const Problem problem = clamped(beam, 0.45, 3);
  const SolverTraits traits = traits_of(problem);
  EXPECT_EQ(traits.dimension, 3);
  EXPECT_EQ(traits.load_cases, 3);
  EXPECT_EQ(traits.poisson, 0.45);
  const int nodes = beam.num_points();
  const int supported = beam.num_points(1) * beam.num_points(2);
  EXPECT_EQ(traits.free_dofs, 3.0 * (nodes - supported));
  const double expected =
      std::sqrt(50.0 * 50.0 * greville_variance(beam.knots(0)) / greville_variance(beam.knots(2)));
  EXPECT_NEAR(traits.aspect, expected, 1e-10 * expected);
  // Near the 50:1 of the extents: 39.7, because the 5 Greville points across 3 elements (0,
  // 1/6, 1/2, 5/6, 1) spread more than the 42 along the length.
  EXPECT_GT(traits.aspect, 35.0);
  EXPECT_LT(traits.aspect, 50.0);

  // The same beam turned by a rotation: the principal extents do not change.
  nurbs::Patch turned = beam;
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  for (int a = 0; a < turned.num_points(); ++a)
    turned.set_control_point(a, rotation * beam.control_point(a));
  Problem rotated = problem;
  rotated.patches = {turned};
  EXPECT_NEAR(traits_of(rotated).aspect, expected, 1e-8 * expected);

  // A cube's control points are the same along every axis.
  EXPECT_NEAR(traits_of(clamped(box({1, 1, 1}, {4, 4, 4}), 0.3)).aspect, 1.0, 1e-12);
}

TEST(SolverChoice, SmallProblemsAreFactorised) {
  SolverTraits traits;
  traits.free_dofs = kAutoIterativeDofs3d;
  traits.poisson = 0.499;
  traits.aspect = 100;
  traits.amg_available = true;
  EXPECT_EQ(choose_solver(traits).method, Method::kCholesky);
  traits.dimension = 2;
  traits.free_dofs = kAutoIterativeDofs2d;
  EXPECT_EQ(choose_solver(traits).method, Method::kCholesky);
}

TEST(SolverChoice, ManyLoadCasesPayForTheFactorisation) {
  SolverTraits traits;
  traits.free_dofs = 114444;
  traits.amg_available = true;
  EXPECT_NE(choose_solver(traits).method, Method::kCholesky);
  traits.load_cases = 200;
  const SolverChoice many = choose_solver(traits);
  EXPECT_EQ(many.method, Method::kCholesky) << many.reason;
  EXPECT_NE(many.reason.find("200 load case(s)"), std::string::npos) << many.reason;
}

TEST(SolverChoice, EstimatesGrowWithTheConditioning) {
  SolverTraits well;
  well.free_dofs = 114444;
  well.amg_available = true;
  SolverTraits soft = well, slender = well;
  soft.poisson = 0.49;
  slender.aspect = 50;
  const SolverChoice a = choose_solver(well), b = choose_solver(soft), c = choose_solver(slender);
  EXPECT_GT(b.cg_seconds, a.cg_seconds);
  EXPECT_GT(c.cg_seconds, a.cg_seconds);
  EXPECT_GT(b.amg_seconds, a.amg_seconds);
  // AMG's iterations depend less on slenderness than block-Jacobi CG's (not on nu: measured).
  EXPECT_LT(c.amg_seconds / a.amg_seconds, c.cg_seconds / a.cg_seconds);
  // A slender part factorises like a band: cheaper than a compact one of the same size.
  EXPECT_LT(c.cholesky_seconds, a.cholesky_seconds);
  // Without PETSc the rule never picks AMG.
  slender.amg_available = false;
  EXPECT_NE(choose_solver(slender).method, Method::kAmg);
  EXPECT_NE(choose_solver(slender).reason.find("AMG not built"), std::string::npos);
}

// Small versions of bench/bench_solvers.cpp's problems (a quarter of the elements per direction,
// built in milliseconds) with the free DOFs of the full size: the rule must pick what was fastest
// there (docs/performance.md): block-Jacobi CG for the cube at nu 0.3 and 0.49 (AMG's V-cycles
// cost more than the iterations they save; the factorisation ~5 x CG), sparse Cholesky for the
// 50:1 cantilever (banded: 8.8 s CPU against CG's thousands of iterations).
TEST(SolverChoice, SmallVersionsOfTheBenchmarksGetTheFastestSolver) {
  struct Case {
    const char* name;
    Problem problem;
    double full_free_dofs;
    Method fastest;
  };
  const Case cases[] = {
      {"cube", clamped(box({1, 1, 1}, {8, 8, 8}), 0.3), 114444, Method::kConjugateGradient},
      {"cube_nu049", clamped(box({1, 1, 1}, {8, 8, 8}), 0.49), 114444, Method::kConjugateGradient},
      {"cantilever", clamped(box({50, 1, 1}, {80, 2, 2}), 0.3), 96300, Method::kCholesky},
  };
  for (const Case& c : cases) {
    SolverTraits traits = traits_of(c.problem);
    traits.free_dofs = c.full_free_dofs;
    traits.amg_available = true;
    const SolverChoice choice = choose_solver(traits);
    EXPECT_EQ(choice.method, c.fastest) << c.name << ": " << choice.reason;
  }
}

}  // namespace
}  // namespace isospring::analysis
