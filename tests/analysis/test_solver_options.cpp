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
