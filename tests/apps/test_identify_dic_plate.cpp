// `isospring identify` on real DIC data (examples/dic_plate): the steel plate with a hole of
// Troeger et al. (../shared/data/dic-steel-plate-hole). Skipped when ../shared is absent.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "run_program.hpp"

namespace isospring {
namespace {

TEST(IdentifyDicPlate, RealDataGiveSteelAndRigidMotion) {
  const std::filesystem::path data =
      std::filesystem::path(ISOSPRING_SHARED_DIR) / "data/dic-steel-plate-hole";
  if (!std::filesystem::exists(data / "displacements_interpolated.csv"))
    GTEST_SKIP() << data << " is absent (the shared reference data sit next to the repository)";
  testing::TemporaryFolder out;
  const auto run = testing::run_isospring(std::string("identify ") + ISOSPRING_SOURCE_DIR +
                                          "/examples/dic_plate/case.json -o " +
                                          out.path().string() + " --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  std::ifstream file(out.path() / "report.json");
  const nlohmann::json report = nlohmann::json::parse(file);
  // The README says the left end moves: the frame's rigid motion must be found.
  const auto& added = report["effects_added"];
  EXPECT_NE(std::find(added.begin(), added.end(), "rigid_offset"), added.end()) << added;
  // Independent check of the identified material: structural steel, E 190-230 GPa (S235 nominal
  // 210 GPa) and nu 0.25-0.35, with the published end traction 106.26 N/mm^2.
  for (const auto& p : report["parameters"]) {
    if (p["name"] == "E") {
      EXPECT_GT(p["value"].get<double>(), 190e9);
      EXPECT_LT(p["value"].get<double>(), 230e9);
    }
    if (p["name"] == "nu") {
      EXPECT_GT(p["value"].get<double>(), 0.25);
      EXPECT_LT(p["value"].get<double>(), 0.35);
    }
  }
  // The effects must explain most of the plain model's residual, also on held-out markers.
  EXPECT_LT(report["rms_after"].get<double>(), 0.5 * report["rms_before"].get<double>());
  EXPECT_LT(report["holdout"]["validation_after"]["rms"].get<double>(),
            0.5 * report["holdout"]["validation_before"]["rms"].get<double>());
}

}  // namespace
}  // namespace isospring
