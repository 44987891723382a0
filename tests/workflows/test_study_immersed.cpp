// `study` on an immersed case (workflows::run_study_immersed): the octant of a hollow sphere
// under internal pressure, cut from B-spline background grids by its exact B-rep (a STEP file
// OpenCascade builds), against the closed form (Timoshenko & Goodier; benchmarks.md). Grid
// refinement must show the optimal rates of the background degree, p + 1 in L2 and p in the
// energy norm, fitted by the study's own report over its last three levels.
#include <gtest/gtest.h>

#include <cstdio>

#include "immersed_test_parts.hpp"
#include "isospring/io/immersed_case.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/workflows/study_immersed.hpp"

namespace isospring::workflows {
namespace {

constexpr double kRi = 1.0, kRo = 2.0, kP = 10.0;

io::ImmersedCase octant_case(const testing::ScratchFolder& dir, int cells, int degree) {
  testing::write_sphere_octant(dir.path, kRi, kRo);
  const auto file = testing::write_json(
      dir.path / "octant.json",
      testing::sphere_octant_case("sphere_octant.step", kRi, kRo, kP, cells, degree));
  return io::read_immersed_case(file);
}

TEST(StudyImmersed, HollowSphereOctantConvergesAtOptimalRates) {
  const testing::ScratchFolder dir("study-immersed");
  const io::ImmersedCase c = octant_case(dir, 4, 2);
  StudyCommandOptions o;
  o.levels = 2;  // 4 and 8 cells per direction
  o.degrees = {2};
  const StudyCommandResult r = run_study_immersed(c, o, io::Progress("study", true));
  ASSERT_EQ(r.rows.size(), 2u);
  EXPECT_EQ(r.analytic_type, "hollow_sphere");
  for (const StudyRow& row : r.rows)
    std::printf("p=%d cells=%d dofs=%d  L2 %.3e  energy %.3e  W %.10g  %.2f s\n", row.degree,
                row.elements, row.dofs, row.l2, row.energy, row.quantity, row.assembly + row.solve);
  const StudyReport report = study_report(r);
  const auto& entry = report.json.at("degrees").at(0);
  const double l2_rate = entry.at("fitted_rate"), energy_rate = entry.at("fitted_energy_rate");
  std::printf("fitted rates: L2 %.3f, energy %.3f\n", l2_rate, energy_rate);
  // Optimal: 3 and 2; the bounds leave 0.4 and 0.25 below them for the coarse grid (measured
  // 2.70 and 1.83, both still rising) and refuse the next lower order.
  EXPECT_GT(l2_rate, 2.6);
  EXPECT_LT(l2_rate, 3.6);
  EXPECT_GT(energy_rate, 1.75);
  EXPECT_LT(energy_rate, 2.5);
  EXPECT_LT(r.rows.back().l2, 1.5e-3);
  EXPECT_EQ(report.json.at("case").at("path"), "immersed");
  EXPECT_EQ(report.json.at("reference"), "analytic:hollow_sphere");
  // The strain energy converges to the exact one, W = P/2 int_inner u_r dA (Clapeyron):
  // u_r(ri) from the closed form over the octant's inner surface (pi ri^2 / 2).
  const double nu = 0.3, E = 1e5;
  const double A = kP * kRi * kRi * kRi / (kRo * kRo * kRo - kRi * kRi * kRi);
  const double ur = A / E * ((1 - 2 * nu) * kRi + (1 + nu) * kRo * kRo * kRo / (2 * kRi * kRi));
  const double exact_energy = 0.5 * kP * ur * M_PI * kRi * kRi / 2;
  // Measured 3.6e-4 off at 8 cells (the energy error squared, 1.6e-2^2 = 2.6e-4, plus the
  // ghost penalty's consistency error).
  EXPECT_NEAR(r.rows.back().quantity, exact_energy, 1e-3 * exact_energy);
}

TEST(StudyImmersed, RefusesAPatchPointQuantity) {
  const testing::ScratchFolder dir("study-immersed-bad");
  const io::ImmersedCase c = octant_case(dir, 2, 2);
  StudyCommandOptions o;
  o.levels = 1;  // refused before any immersion
  o.quantity = "displacement";
  o.point = "0:1,0.5,0.5";
  try {
    run_study_immersed(c, o, io::Progress("study", true));
    FAIL() << "no error";
  } catch (const nurbs::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("strain_energy"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace isospring::workflows
