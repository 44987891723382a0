// Immersed B-bar selected by a case file ("analysis": {"volumetric": "bbar"}) through the
// workflows: the octant of a hollow sphere under internal pressure (a STEP file OpenCascade
// builds) at nu = 0.49, cut from quadratic background grids, against the closed form
// (Timoshenko & Goodier; benchmarks.md). B-bar must converge at least at second order and beat
// the displacement formulation, which locks on the coarse grids, by the measured factors. Bad
// combinations are refused with the field named.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "immersed_test_parts.hpp"
#include "isospring/io/immersed_case.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/workflows/study_immersed.hpp"

namespace isospring::workflows {
namespace {

constexpr double kRi = 1.0, kRo = 2.0, kP = 10.0, kNu = 0.49;

nlohmann::json octant_document(const std::string& volumetric) {
  nlohmann::json j = testing::sphere_octant_case("sphere_octant.step", kRi, kRo, kP, 4, 2);
  j["material"]["nu"] = kNu;
  if (!volumetric.empty()) j["analysis"] = {{"volumetric", volumetric}};
  return j;
}

io::ImmersedCase octant_case(const testing::ScratchFolder& dir, const nlohmann::json& j) {
  testing::write_sphere_octant(dir.path, kRi, kRo);
  return io::read_immersed_case(testing::write_json(dir.path / "octant.json", j));
}

StudyCommandResult study(const io::ImmersedCase& c) {
  StudyCommandOptions o;
  o.levels = 2;  // 4 and 8 cells per direction
  o.degrees = {2};
  return run_study_immersed(c, o, io::Progress("study", true));
}

TEST(ImmersedBbarCase, NearlyIncompressibleOctantConvergesWithBbarAndLocksWithout) {
  const testing::ScratchFolder dir("immersed-bbar-case");
  const io::ImmersedCase bbar_case = octant_case(dir, octant_document("bbar"));
  const io::ImmersedCase disp_case = octant_case(dir, octant_document(""));
  ASSERT_EQ(bbar_case.volumetric, analysis::Volumetric::kBbar);
  ASSERT_EQ(disp_case.volumetric, analysis::Volumetric::kDisplacement);
  EXPECT_EQ(io::immersed_options(bbar_case, bbar_case.load_cases[0]).volumetric,
            analysis::Volumetric::kBbar);
  const StudyCommandResult bbar = study(bbar_case), disp = study(disp_case);
  ASSERT_EQ(bbar.rows.size(), 2u);
  ASSERT_EQ(disp.rows.size(), 2u);
  for (const auto* r : {&bbar, &disp})
    for (const StudyRow& row : r->rows)
      std::printf("%s cells=%d dofs=%d  L2 %.3e  energy %.3e  W %.10g\n",
                  r == &bbar ? "bbar" : "disp", row.elements, row.dofs, row.l2, row.energy,
                  row.quantity);
  const StudyReport report = study_report(bbar);
  EXPECT_EQ(report.json.at("case").at("volumetric"), "bbar");
  EXPECT_EQ(study_report(disp).json.at("case").at("volumetric"), "displacement");
  const auto& entry = report.json.at("degrees").at(0);
  const double l2_rate = entry.at("fitted_rate"), energy_rate = entry.at("fitted_energy_rate");
  const double disp_rate = study_report(disp).json.at("degrees").at(0).at("fitted_rate");
  std::printf("fitted rates: bbar L2 %.3f energy %.3f; displacement L2 %.3f\n", l2_rate,
              energy_rate, disp_rate);
  // The strain energy converges to the exact compliance, W = P/2 int_inner u_r dA (Clapeyron).
  const double E = 1e5;
  const double A = kP * kRi * kRi * kRi / (kRo * kRo * kRo - kRi * kRi * kRi);
  const double ur = A / E * ((1 - 2 * kNu) * kRi + (1 + kNu) * kRo * kRo * kRo / (2 * kRi * kRi));
  const double exact_energy = 0.5 * kP * ur * M_PI * kRi * kRi / 2;
  const auto energy_error = [&](const StudyRow& row) {
    return std::abs(row.quantity - exact_energy) / exact_energy;
  };
  for (size_t k = 0; k < 2; ++k)
    std::printf("level %zu: L2 ratio disp/bbar %.2f, energy error bbar %.2e disp %.2e\n", k,
                disp.rows[k].l2 / bbar.rows[k].l2, energy_error(bbar.rows[k]),
                energy_error(disp.rows[k]));
  // Measured (docs/immersed.md, "B-bar in case files"): L2 rate 2.13 and energy-norm rate 1.81
  // over 4 -> 8 cells (below the optimal 3 and 2: the coarse grids are pre-asymptotic and the
  // mean-dilatation pressure is only O(h) on the cut cells); the bounds refuse first order.
  EXPECT_GT(l2_rate, 1.9);
  EXPECT_LT(l2_rate, 3.6);
  EXPECT_GT(energy_rate, 1.6);
  EXPECT_LT(energy_rate, 2.5);
  // The displacement formulation locks on the coarse grid: measured L2 errors 2.5 and 1.5 times
  // B-bar's and strain-energy errors 13 and 3.8 times B-bar's on 4 and 8 cells.
  EXPECT_LT(bbar.rows[0].l2 * 2, disp.rows[0].l2);
  EXPECT_LT(bbar.rows[1].l2 * 1.3, disp.rows[1].l2);
  EXPECT_LT(energy_error(bbar.rows[0]) * 8, energy_error(disp.rows[0]));
  EXPECT_LT(energy_error(bbar.rows[1]) * 2.5, energy_error(disp.rows[1]));
  EXPECT_LT(bbar.rows.back().l2, 4e-3);
  EXPECT_NEAR(bbar.rows.back().quantity, exact_energy, 1e-3 * exact_energy);
}

void expect_refused(const nlohmann::json& j, const std::string& field, const std::string& text) {
  const testing::ScratchFolder dir("immersed-bbar-bad");
  try {
    octant_case(dir, j);
    FAIL() << "no error for " << j.at("analysis").dump();
  } catch (const nurbs::InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("octant.json"), std::string::npos) << m;
    EXPECT_NE(m.find(field), std::string::npos) << m;
    EXPECT_NE(m.find(text), std::string::npos) << m;
  }
}

TEST(ImmersedBbarCase, BadCombinationsNameTheField) {
  nlohmann::json j = octant_document("bar");
  expect_refused(j, "volumetric", "unknown volumetric treatment 'bar'");
  j["analysis"] = {{"type", "plane_strain"}, {"volumetric", "bbar"}};
  expect_refused(j, "type", "an immersed CAD part is a 3D solid");
  j["analysis"] = {{"volumetric", "bbar"}, {"thickness", 1.0}};
  expect_refused(j, "thickness", "thickness");
}

}  // namespace
}  // namespace isospring::workflows
