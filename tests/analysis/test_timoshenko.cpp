// Timoshenko cantilever (benchmarks.md): plane stress, end shear P, clamp by the exact
// displacement (L2-projected on the clamped side). The exact field is a cubic polynomial, so
// degree 3 reproduces it to round-off and degree 2 converges to it.
#include <gtest/gtest.h>

#include "analysis_models.hpp"
#include "isospring/analysis/post_processing.hpp"
#include "isospring/analysis/static_solver.hpp"

namespace isospring::analysis {
namespace {

constexpr double kLength = 8.0, kDepth = 1.0, kLoad = 1.0, kE = 1000.0, kNu = 0.25;
constexpr double kI = kDepth * kDepth * kDepth / 12.0;

Eigen::Vector3d exact_u(const Eigen::Vector3d& x) {
  const double X = x.x(), y = x.y(), L = kLength, D = kDepth;
  return {kLoad * y / (6 * kE * kI) * ((6 * L - 3 * X) * X + (2 + kNu) * (y * y - D * D / 4)),
          -kLoad / (6 * kE * kI) *
              (3 * kNu * y * y * (L - X) + (4 + 5 * kNu) * D * D * X / 4 + (3 * L - X) * X * X),
          0.0};
}

Eigen::Matrix3d exact_stress(const Eigen::Vector3d& x) {
  Eigen::Matrix3d s = Eigen::Matrix3d::Zero();
  s(0, 0) = kLoad * (kLength - x.x()) * x.y() / kI;
  s(0, 1) = s(1, 0) = -kLoad / (2 * kI) * (kDepth * kDepth / 4 - x.y() * x.y());
  return s;
}

Problem cantilever(int degree, int nx, int ny) {
  Problem problem;
  problem.formulation = Formulation::kPlaneStress;
  problem.material = {kE, kNu, 1.0, 1.0};
  problem.patches.push_back(testing::beam(kLength, kDepth, degree, nx, ny));
  Support clamp;
  clamp.side = {0, 0, 0};
  clamp.fixed = {true, true, false};
  clamp.value_function = exact_u;
  problem.supports.push_back(clamp);
  LoadCase load;
  load.id = "end shear";
  Traction shear;
  shear.side = {0, 0, 1};
  shear.function = [](const Eigen::Vector3d& x, const Eigen::Vector3d& n) -> Eigen::Vector3d {
    return exact_stress(x) * n;
  };
  load.tractions.push_back(shear);
  problem.load_cases.push_back(load);
  return problem;
}

TEST(Timoshenko, CubicSplinesReproduceTheExactTipDeflection) {
  const Problem problem = cantilever(3, 8, 2);
  const StaticResult result = solve_static(problem);
  const auto& u = result.load_cases[0].control_displacements;
  const FieldPoint tip = evaluate_field(problem, u, 0, {1.0, 0.5, 0.0});
  const double exact = exact_u(tip.point).y();
  // Tip deflection P L^3 / (3 E I) (1 + shear terms) = -0.2048 (1 + ...)
  EXPECT_NEAR(exact,
              -kLoad * std::pow(kLength, 3) / (3 * kE * kI) -
                  kLoad * (4 + 5 * kNu) * kDepth * kDepth * kLength / (24 * kE * kI),
              1e-12);
  EXPECT_LT(std::abs(tip.displacement.y() - exact), 1e-9 * std::abs(exact));
  const ErrorNorms errors = error_norms(problem, u, exact_u, exact_stress);
  EXPECT_LT(errors.relative_l2(), 1e-9);
  EXPECT_LT(errors.relative_energy(), 1e-8);
  // Reactions at the clamp balance the end shear P (downwards load, upwards reaction).
  EXPECT_NEAR(result.load_cases[0].reaction_sum.y(), kLoad, 1e-9);
  EXPECT_NEAR(result.load_cases[0].reaction_sum.x(), 0.0, 1e-9);
  // Strain energy = work of the load = 1/2 u^T K u, and the integral form agrees.
  EXPECT_NEAR(strain_energy(problem, u), result.load_cases[0].strain_energy,
              1e-10 * result.load_cases[0].strain_energy);
}

TEST(Timoshenko, QuadraticSplinesConvergeToTipDeflection) {
  std::vector<double> h, l2, energy;
  double tip_error = 0.0;
  for (int n : {2, 4, 8, 16}) {
    const Problem problem = cantilever(2, 4 * n, n);
    const auto u = solve_static(problem).load_cases[0].control_displacements;
    const ErrorNorms errors = error_norms(problem, u, exact_u, exact_stress);
    h.push_back(1.0 / n);
    l2.push_back(errors.relative_l2());
    energy.push_back(errors.relative_energy());
    const FieldPoint tip = evaluate_field(problem, u, 0, {1.0, 0.5, 0.0});
    tip_error = std::abs(tip.displacement.y() / exact_u(tip.point).y() - 1.0);
  }
  EXPECT_GE(testing::fitted_rate(h, l2, 3), 2.9);
  EXPECT_GE(testing::fitted_rate(h, energy, 3), 1.9);
  EXPECT_LT(tip_error, 1e-6);
}

}  // namespace
}  // namespace isospring::analysis
