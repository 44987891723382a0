// Solver options: preconditioned conjugate gradients agree with the Cholesky solve; several load
// cases share one factorisation and superpose.
#include <gtest/gtest.h>

#include "analysis_models.hpp"
#include "isospring/analysis/static_solver.hpp"

namespace isospring::analysis {
namespace {

Problem ring_problem() {
  Problem problem;
  problem.formulation = Formulation::kPlaneStrain;
  problem.material = {1e5, 0.3, 1.0, 1.0};
  problem.patches.push_back(nurbs::k_refine(testing::quarter_ring(), {3, 3, 0}, {8, 8, 1}));
  for (int end = 0; end < 2; ++end) {
    Support symmetry;
    symmetry.side = {0, 1, end};
    symmetry.symmetry = true;
    problem.supports.push_back(symmetry);
  }
  LoadCase pressure;
  pressure.id = "pressure";
  pressure.pressures.push_back({{0, 0, 0}, 100.0});
  LoadCase body;
  body.id = "body";
  body.body_force = {0.0, -50.0, 0.0};
  LoadCase both;
  both.id = "both";
  both.pressures = pressure.pressures;
  both.body_force = body.body_force;
  problem.load_cases = {pressure, body, both};
  return problem;
}

TEST(SolverOptions, ConjugateGradientsMatchCholesky) {
  const Problem problem = ring_problem();
  const StaticResult direct = solve_static(problem);
  SolverOptions options;
  options.method = SolverOptions::Method::kConjugateGradient;
  options.cg_tolerance = 1e-12;
  const StaticResult iterative = solve_static(problem, options);
  for (size_t l = 0; l < problem.load_cases.size(); ++l) {
    const Eigen::VectorXd& a = direct.load_cases[l].displacement;
    const Eigen::VectorXd& b = iterative.load_cases[l].displacement;
    EXPECT_LT((a - b).norm(), 1e-8 * a.norm()) << problem.load_cases[l].id;
  }
}

// 3D, curved (rational) and with a prescribed non-zero displacement: the iterative solver's
// elimination of supports (unit rows in the node blocks, the coupling K_fc u_c moved to the
// right-hand side) and its block-Jacobi preconditioner on blocks that couple the components.
TEST(SolverOptions, ConjugateGradientsMatchCholeskyWithPrescribedDisplacements) {
  Problem problem;
  problem.formulation = Formulation::kSolid;
  problem.material = {1e5, 0.3, 1.0, 1.0};
  problem.patches.push_back(
      nurbs::k_refine(testing::sphere_octant(1.0, 2.0), {2, 2, 2}, {4, 4, 3}));
  for (const Side side : {Side{0, 0, 0}, Side{0, 0, 1}, Side{0, 1, 0}}) {
    Support symmetry;
    symmetry.side = side;
    symmetry.symmetry = true;
    problem.supports.push_back(symmetry);
  }
  Support pulled;  // one control point of the outer surface (6 x 6 x 5 net) moved up by 1e-3
  pulled.side = {0, 2, 1};
  pulled.control_point = 2 + 6 * (2 + 6 * 4);
  pulled.fixed = {false, false, true};
  pulled.value = {0.0, 0.0, 1e-3};
  problem.supports.push_back(pulled);
  LoadCase load;
  load.id = "pressure";
  load.pressures.push_back({{0, 2, 0}, 10.0});
  problem.load_cases = {load};
  const StaticResult direct = solve_static(problem);
  SolverOptions options;
  options.method = SolverOptions::Method::kConjugateGradient;
  options.cg_tolerance = 1e-12;
  const StaticResult iterative = solve_static(problem, options);
  const LoadCaseResult& a = direct.load_cases[0];
  const LoadCaseResult& b = iterative.load_cases[0];
  EXPECT_LT((a.displacement - b.displacement).norm(), 1e-9 * a.displacement.norm());
  EXPECT_LT((a.reaction_sum - b.reaction_sum).norm(), 1e-7 * a.reaction_sum.norm());
  EXPECT_GT(a.reaction_sum.norm(), 0.0);
  EXPECT_GT(b.iterations, 0);
  EXPECT_LT(b.relative_residual, 1e-11);
  EXPECT_EQ(a.iterations, 0);
}

TEST(SolverOptions, AutoChoosesByDimensionAndFreeDofs) {
  using Method = SolverOptions::Method;
  EXPECT_EQ(choose_solver(3, 3000).method, Method::kCholesky);
  EXPECT_EQ(choose_solver(3, kAutoIterativeDofs3d).method, Method::kCholesky);
  EXPECT_EQ(choose_solver(3, kAutoIterativeDofs3d + 1).method, Method::kConjugateGradient);
  EXPECT_EQ(choose_solver(3, 114444).method, Method::kConjugateGradient);
  // 2D factors stay small much longer: the 256^2 square (133,128 DOFs) stays direct.
  EXPECT_EQ(choose_solver(2, 133128).method, Method::kCholesky);
  EXPECT_EQ(choose_solver(2, 2e6).method, Method::kConjugateGradient);
  const std::string reason = choose_solver(3, 114444).reason;
  EXPECT_NE(reason.find("114444 free DOFs in 3D above 20000"), std::string::npos) << reason;
  EXPECT_NE(choose_solver(2, 1000).reason.find("sparse Cholesky"), std::string::npos);
}

// kAuto solves with what it chose, and exactly as the explicit method would: the small ring
// directly, a 3D cube of 22,800 free DOFs (above the threshold) iteratively.
TEST(SolverOptions, AutoEqualsTheExplicitMethodItChose) {
  SolverOptions automatic;
  automatic.method = SolverOptions::Method::kAuto;
  const Problem ring = ring_problem();
  const StaticResult small = solve_static(ring, automatic);
  EXPECT_EQ(small.method, SolverOptions::Method::kCholesky);
  EXPECT_NE(small.method_reason.find("2D at or below"), std::string::npos) << small.method_reason;
  const StaticResult direct = solve_static(ring);
  EXPECT_TRUE(direct.method_reason.empty());
  for (size_t l = 0; l < ring.load_cases.size(); ++l)
    EXPECT_EQ(small.load_cases[l].displacement, direct.load_cases[l].displacement);

  Problem cube;
  cube.formulation = Formulation::kSolid;
  cube.material = {210e9, 0.3, 7800, 1.0};
  const nurbs::KnotVector linear(1, {0, 0, 1, 1});
  std::vector<Eigen::Vector3d> corners;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) corners.emplace_back(i, j, k);
  // Trilinear (cheap to assemble), 20^3 control points.
  cube.patches.push_back(
      nurbs::k_refine(nurbs::Patch({linear, linear, linear}, corners), {1, 1, 1}, {19, 19, 19}));
  Support clamp;
  clamp.side = {0, 0, 0};
  clamp.fixed = {true, true, true};
  cube.supports.push_back(clamp);
  LoadCase tension;
  tension.id = "tension";
  tension.tractions.push_back({{0, 0, 1}, {1e6, 0, 0}, {}});
  cube.load_cases.push_back(tension);
  const StaticResult large = solve_static(cube, automatic);
  EXPECT_EQ(large.method, SolverOptions::Method::kConjugateGradient);
  EXPECT_NE(large.method_reason.find("22800 free DOFs in 3D above"), std::string::npos)
      << large.method_reason;
  SolverOptions cg;
  cg.method = SolverOptions::Method::kConjugateGradient;
  const StaticResult explicit_cg = solve_static(cube, cg);
  EXPECT_EQ(large.load_cases[0].iterations, explicit_cg.load_cases[0].iterations);
  const Eigen::VectorXd& u = explicit_cg.load_cases[0].displacement;
  EXPECT_LT((large.load_cases[0].displacement - u).norm(), 1e-12 * u.norm());
}

TEST(SolverOptions, LoadCasesSuperposeAndReactionsBalance) {
  const StaticResult result = solve_static(ring_problem());
  ASSERT_EQ(result.load_cases.size(), 3u);
  const Eigen::VectorXd sum = result.load_cases[0].displacement + result.load_cases[1].displacement;
  EXPECT_LT((sum - result.load_cases[2].displacement).norm(),
            1e-12 * result.load_cases[2].displacement.norm());
  // Body force -50 in y over the quarter ring area 3 pi / 4: the supports carry all of it
  // (pressure on a quarter ring is balanced by the symmetry supports in x and y separately).
  const double weight = -50.0 * 3.0 * M_PI / 4.0;
  EXPECT_NEAR(result.load_cases[1].reaction_sum.y(), -weight, 1e-8 * std::abs(weight));
  EXPECT_NEAR(result.load_cases[1].reaction_sum.x(), 0.0, 1e-8 * std::abs(weight));
  // Pressure P on the inner quarter arc: resultant P * Ri in -x and -y on the body... pushed
  // outwards: force (P Ri, P Ri); reactions -(P Ri, P Ri).
  EXPECT_NEAR(result.load_cases[0].reaction_sum.x(), -100.0, 1e-8 * 100.0);
  EXPECT_NEAR(result.load_cases[0].reaction_sum.y(), -100.0, 1e-8 * 100.0);
  EXPECT_GT(result.load_cases[0].strain_energy, 0.0);
}

}  // namespace
}  // namespace isospring::analysis
