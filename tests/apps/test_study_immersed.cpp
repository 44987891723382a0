// End-to-end: `isospring study` on an immersed case (examples/immersed/cylinder_gravity.json):
// level 0 of the study is the same analysis as `isospring analyze` of the case, so its strain
// energy must equal analyze's; another degree adds its rows and keeps the report's shape (the rates
// themselves are tested against a closed form in tests/workflows/test_study_immersed.cpp). The
// commands without an immersed form refuse the case before writing anything, with the reason.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>

#include "run_program.hpp"

using isospring::testing::example;
using isospring::testing::read_json;
using isospring::testing::run_isospring;
using isospring::testing::TemporaryFolder;
using nlohmann::json;

namespace {

TEST(StudyImmersed, LevelZeroIsAnalyzeAndDegreesAreElevated) {
  TemporaryFolder out;
  const std::string case_file = example("immersed/cylinder_gravity.json");
  auto run = run_isospring("analyze " + case_file + " -o " + (out / "analyze") + " --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const double analyzed =
      read_json(out.path() / "analyze" / "report.json")["load_cases"][0]["strain_energy"];
  run = run_isospring("study " + case_file + " -o " + (out / "study") +
                      " --levels 1 --degrees 2,1 --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const json report = read_json(out.path() / "study" / "report.json");
  EXPECT_EQ(report["case"]["path"], "immersed");
  EXPECT_EQ(report["load_case"], "gravity");
  ASSERT_EQ(report["degrees"].size(), 2u);
  const json& p2 = report["degrees"][0]["levels"][0];
  const json& p1 = report["degrees"][1]["levels"][0];
  EXPECT_EQ(p2["elements"], 4);  // the case's 4 x 4 x 4 cells
  EXPECT_NEAR(p2["quantity"].get<double>(), analyzed, 1e-9 * analyzed);
  // Degree 1 on the same cells (degree 3 costs 45 s of CPU there): fewer DOFs ((4 + 1)^3
  // background functions at most, x 3) and a stiffer, less converged model: trilinear cells
  // lock in bending, so its strain energy lies below degree 2's (measured 7.150e-9 with 375
  // DOFs against 7.748e-9 with 648).
  EXPECT_LT(p1["dofs"].get<int>(), p2["dofs"].get<int>());
  EXPECT_LE(p1["dofs"].get<int>(), 3 * 5 * 5 * 5);
  EXPECT_LT(p1["quantity"].get<double>(), p2["quantity"].get<double>());
  std::printf("cylinder study: p=2 W %.6e (%d DOFs), p=1 W %.6e (%d DOFs)\n",
              p2["quantity"].get<double>(), p2["dofs"].get<int>(), p1["quantity"].get<double>(),
              p1["dofs"].get<int>());
  EXPECT_TRUE(std::filesystem::exists(out.path() / "study" / "study.csv"));
  EXPECT_TRUE(std::filesystem::exists(out.path() / "study" / "report.md"));
}

TEST(StudyImmersed, CommandsWithoutAnImmersedFormRefuseItWithTheReason) {
  TemporaryFolder out;
  const std::string case_file = example("immersed/cylinder_gravity.json");
  struct Refusal {
    std::string command, output, reason;
  };
  for (const Refusal& r : {Refusal{"export-calculix", "deck.inp", "needs a mesh of the part"},
                           Refusal{"export-step", "part.step", "the CAD file itself"}}) {
    const auto run = run_isospring(r.command + " " + case_file + " -o " + (out / r.output));
    EXPECT_NE(run.exit_code, 0) << r.command;
    EXPECT_NE(run.output.find("an immersed case"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find(r.reason), std::string::npos) << run.output;
    EXPECT_NE(run.output.find(
                  "`isospring analyze`, `study`, `calibrate` and `identify` run immersed cases"),
              std::string::npos)
        << run.output;
    EXPECT_FALSE(std::filesystem::exists(out.path() / r.output)) << r.command;
  }
}

// --quantity displacement names a patch point; an immersed case has none.
TEST(StudyImmersed, PatchPointQuantityIsRefused) {
  TemporaryFolder out;
  const auto run = run_isospring("study " + example("immersed/cylinder_gravity.json") + " -o " +
                                 (out / "s") + " --quantity displacement --point 0:1,0,0 --quiet");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.output.find("use --quantity strain_energy or max_displacement"), std::string::npos)
      << run.output;
  EXPECT_FALSE(std::filesystem::exists(out.path() / "s" / "report.json"));
}

}  // namespace
