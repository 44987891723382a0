// Hollow sphere under internal pressure (3D Lame), octant of a thick sphere with symmetry planes.
#include <gtest/gtest.h>

#include <cstdio>

#include "analysis_models.hpp"
#include "isospring/analysis/post_processing.hpp"
#include "isospring/analysis/static_solver.hpp"

namespace isospring::analysis {
namespace {

constexpr double kRi = 1.0, kRo = 2.0, kE = 1000.0, kNu = 0.3, kP = 1.0;
constexpr double kC = kP * kRi * kRi * kRi / (kRo * kRo * kRo - kRi * kRi * kRi);

Eigen::Vector3d exact_u(const Eigen::Vector3d& x) {
  const double r = x.norm();
  const double ur = kC / kE * ((1 - 2 * kNu) * r + (1 + kNu) * kRo * kRo * kRo / (2 * r * r));
  return x * (ur / r);
}

Eigen::Matrix3d exact_stress(const Eigen::Vector3d& x) {
  const double r = x.norm(), q = kRo * kRo * kRo / (r * r * r);
  const double srr = kC * (1 - q), stt = kC * (1 + q / 2);
  const Eigen::Vector3d n = x / r;
  return stt * Eigen::Matrix3d::Identity() + (srr - stt) * n * n.transpose();
}

Problem sphere(int p, int splits) {
  Problem problem;
  problem.formulation = Formulation::kSolid;
  problem.material = {kE, kNu, 1.0, 1.0};
  problem.patches.push_back(
      nurbs::k_refine(testing::sphere_octant(kRi, kRo), {p, p, p}, {splits, splits, splits}));
  // u0: plane y = 0, u1: plane x = 0, v0: plane z = 0. v1 is the collapsed pole line.
  for (const Side side : {Side{0, 0, 0}, Side{0, 0, 1}, Side{0, 1, 0}}) {
    Support symmetry;
    symmetry.side = side;
    symmetry.symmetry = true;
    problem.supports.push_back(symmetry);
  }
  LoadCase load;
  load.id = "internal pressure";
  load.pressures.push_back({{0, 2, 0}, kP});
  problem.load_cases.push_back(load);
  return problem;
}

TEST(HollowSphere, RatesAndInnerDisplacement) {
  for (int p : {2, 3}) {
    std::vector<double> h, l2, energy;
    double inner_error = 0.0;
    for (int splits : {2, 4, 8}) {
      const Problem problem = sphere(p, splits);
      const auto u = solve_static(problem).load_cases[0].control_displacements;
      const ErrorNorms e = error_norms(problem, u, exact_u, exact_stress);
      h.push_back(1.0 / splits);
      l2.push_back(e.relative_l2());
      energy.push_back(e.relative_energy());
      const FieldPoint f = evaluate_field(problem, u, 0, {0.3, 0.4, 0.0});
      inner_error = std::abs(f.displacement.norm() / exact_u(f.point).norm() - 1.0);
    }
    const double l2_rate = testing::fitted_rate(h, l2, 2);
    const double energy_rate = testing::fitted_rate(h, energy, 2);
    std::printf(
        "Sphere p=%d: L2 %.3e -> %.3e rate %.3f, energy %.3e -> %.3e rate %.3f, inner u_r "
        "relative error %.2e\n",
        p, l2.front(), l2.back(), l2_rate, energy.front(), energy.back(), energy_rate, inner_error);
    // p = 2 is asymptotic by 8^3 elements; p = 3 is still approaching (measured 3.77 / 2.84 over
    // 4-8, as for the 2D Lame and Kirsch cases whose rates keep rising on finer levels), so it
    // gets 0.25 of slack rather than a finer level that would cost seconds.
    const double slack = p == 2 ? 0.1 : 0.25;
    EXPECT_GE(l2_rate, p + 1 - slack);
    EXPECT_GE(energy_rate, p - slack);
    EXPECT_LT(inner_error, p == 2 ? 1e-4 : 1e-6);
  }
}

}  // namespace
}  // namespace isospring::analysis
