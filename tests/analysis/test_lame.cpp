// Thick-walled cylinder under internal pressure (Lame), plane strain, exact quarter ring.
#include <gtest/gtest.h>

#include <cstdio>

#include "analysis_models.hpp"
#include "isospring/analysis/post_processing.hpp"
#include "isospring/analysis/static_solver.hpp"
#include "lame_cylinder.hpp"

namespace isospring::analysis {
namespace {

using Lame = testing::LameCylinder;

Problem cylinder(const Lame& lame, const nurbs::Patch& patch) {
  return testing::lame_cylinder(lame, patch);
}
nurbs::Patch ring(int p, int n, double weight = testing::kSqrtHalf) {
  return testing::lame_ring(p, n, weight);
}
constexpr double kRi = testing::kLameRi;

// benchmarks.md: E = 1, nu = 0, P = 1, degree 3, C2, 9x9 elements, 288 DOFs, "L2 error
// 1.53640513551293e-06". That number is the ABSOLUTE L2 norm of u - u_h integrated with p + 1 = 4
// Gauss points per direction (the solve's own rule); we reproduce it to 13 digits. Integrated
// accurately (p + 3 points and more) the same solution's L2 error is 1.5931447e-06: the published
// protocol under-integrates the error by 3.6 %.
TEST(Lame, PublicReferenceValueDegree3NineByNine) {
  const Lame lame{1.0, 0.0, 1.0};
  const auto exact_u = [&](const Eigen::Vector3d& x) { return lame.displacement(x); };
  const auto exact_stress = [&](const Eigen::Vector3d& x) { return lame.stress(x); };
  const Problem problem = cylinder(lame, ring(3, 9));
  const StaticResult result = solve_static(problem);
  ASSERT_EQ(result.dofs, 288);
  const auto& u = result.load_cases[0].control_displacements;
  const ErrorNorms published = error_norms(problem, u, exact_u, exact_stress, 4);
  EXPECT_NEAR(published.l2_error, 1.53640513551293e-06, 1e-11 * 1.53640513551293e-06);
  const ErrorNorms accurate = error_norms(problem, u, exact_u, exact_stress);
  const ErrorNorms more = error_norms(problem, u, exact_u, exact_stress, 10);
  EXPECT_NEAR(accurate.l2_error, 1.5931447e-06, 1e-13);
  EXPECT_NEAR(more.l2_error, accurate.l2_error, 1e-7 * accurate.l2_error);
  // The rounded weight 0.7071068 printed in benchmarks.md changes the geometry by ~1e-8 only.
  const Problem rounded = cylinder(lame, ring(3, 9, 0.7071068));
  const ErrorNorms r = error_norms(
      rounded, solve_static(rounded).load_cases[0].control_displacements, exact_u, exact_stress, 4);
  EXPECT_NEAR(r.l2_error, published.l2_error, 1e-3 * published.l2_error);
  std::printf(
      "Lame p=3 9x9: L2 (4 points) %.15g, L2 (6 points) %.15g, relative %.3e, rounded "
      "weight %.15g\n",
      published.l2_error, accurate.l2_error, accurate.relative_l2(), r.l2_error);
}

TEST(Lame, InnerRadialDisplacementAndRates) {
  const Lame lame{1e5, 0.3, 100.0};
  const double exact_inner = lame.radial(kRi);
  {
    const Problem problem = cylinder(lame, ring(3, 8));
    const auto u = solve_static(problem).load_cases[0].control_displacements;
    for (double v : {0.0, 0.3, 1.0}) {
      const FieldPoint f = evaluate_field(problem, u, 0, {0.0, v, 0.0});
      EXPECT_NEAR(f.displacement.norm() / exact_inner, 1.0, 1e-6) << "v = " << v;
    }
  }
  for (int p : {2, 3, 4}) {
    std::vector<double> h, l2, energy;
    for (int n : {8, 16, 32, 64}) {
      const Problem problem = cylinder(lame, ring(p, n));
      const auto u = solve_static(problem).load_cases[0].control_displacements;
      const ErrorNorms e = error_norms(
          problem, u, [&](const Eigen::Vector3d& x) { return lame.displacement(x); },
          [&](const Eigen::Vector3d& x) { return lame.stress(x); });
      h.push_back(1.0 / n);
      l2.push_back(e.relative_l2());
      energy.push_back(e.relative_energy());
    }
    // The exact field has derivatives ~ (p+1)! / r^(p+2): the asymptotic range starts late
    // (uniform knots; per halving 4 -> 128, p = 3: L2 3.77 3.83 3.91 3.96 3.98, energy 2.85 2.89
    // 2.94 2.97 2.98; p = 4 to 64: L2 4.28 4.72 4.91 4.97, energy 3.50 3.73 3.88 3.95: the deficit
    // halves with h), so levels 8..64 and a fit over the last two (benchmarks.md). Measured:
    // p = 2 L2 3.00, energy 2.00; p = 3 3.96 / 2.97; p = 4 4.97 / 3.95.
    const double l2_rate = testing::fitted_rate(h, l2, 2);
    const double energy_rate = testing::fitted_rate(h, energy, 2);
    std::printf("Lame p=%d: L2 %.3e -> %.3e rate %.3f, energy %.3e -> %.3e rate %.3f\n", p,
                l2.front(), l2.back(), l2_rate, energy.front(), energy.back(), energy_rate);
    EXPECT_GE(l2_rate, p + 1 - 0.1);
    EXPECT_GE(energy_rate, p - 0.1);
  }
}

}  // namespace
}  // namespace isospring::analysis
