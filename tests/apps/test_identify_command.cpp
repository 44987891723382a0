// `isospring identify` end to end on the shipped example: hidden gravity and rigid motion found,
// residual at the noise level; markers off the model are an input error unless dropped.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "run_program.hpp"

namespace isospring {
namespace {

const std::string kExample =
    std::string(ISOSPRING_SOURCE_DIR) + "/examples/identify/plate_hidden_gravity.json";

TEST(IdentifyCommand, FindsTheHiddenEffectsOfTheExample) {
  testing::TemporaryFolder out;
  const auto run =
      testing::run_isospring("identify " + kExample + " -o " + out.path().string() + " --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  std::ifstream file(out.path() / "report.json");
  const nlohmann::json report = nlohmann::json::parse(file);
  // The data's two load cases have different rigid motions (re-seated specimen): per load case.
  EXPECT_EQ(report["effects_added"], nlohmann::json({"gravity", "rigid_offset_per_load"}));
  // Leave one load case out: refitted without it, the model with effects predicts it to the
  // noise level (its own rigid motion fitted on it), the nominal one is 30x off.
  ASSERT_EQ(report["load_case_holdout"].size(), 2u);
  for (const auto& h : report["load_case_holdout"]) {
    EXPECT_LT(h["after"]["rms"].get<double>(), 1.3e-6) << h;
    EXPECT_GT(h["before"]["rms"].get<double>(), 10 * h["after"]["rms"].get<double>()) << h;
    EXPECT_EQ(h["local_parameters"], 3) << h;
  }
  // The data carry 1e-6 m noise (examples/identify/plate_hidden_gravity.json).
  EXPECT_LT(report["rms_after"].get<double>(), 1.3e-6);
  EXPECT_GT(report["rms_before"].get<double>(), 10 * report["rms_after"].get<double>());
  for (const auto& p : report["parameters"])
    if (p["name"] == "gy") {
      EXPECT_LT(std::abs(p["value"].get<double>() + 9.81), 3 * p["standard_error"].get<double>());
    }
  EXPECT_TRUE(report.contains("holdout"));
  EXPECT_TRUE(std::filesystem::exists(out.path() / "report.md"));
  EXPECT_TRUE(std::filesystem::exists(out.path() / "markers_L1_after.vtp"));
}

// Bad input of the measured-data loop: NaN in the data, a DOF budget that allows no refinement.
// Exit 1 with a message that names the file, the field and the fix, and no output folder.
TEST(IdentifyCommand, NaNDataAndAHopelessDofBudgetAreInputErrors) {
  testing::TemporaryFolder out;
  const std::filesystem::path folder = out.path() / "case";
  std::filesystem::create_directories(folder);
  std::filesystem::copy_file(kExample, folder / "case.json");
  {
    std::ifstream in(std::string(ISOSPRING_SOURCE_DIR) + "/examples/identify/markers.csv");
    std::ofstream csv(folder / "markers.csv");
    std::string line;
    for (int row = 1; std::getline(in, line); ++row)
      csv << (row == 5 ? line.substr(0, line.rfind(',')) + ",nan" : line) << "\n";
  }
  const auto nan_run = testing::run_isospring("identify " + (folder / "case.json").string() +
                                              " -o " + (out.path() / "nan").string() + " --quiet");
  EXPECT_EQ(nan_run.exit_code, 1) << nan_run.output;
  EXPECT_NE(nan_run.output.find("markers.csv: row 5"), std::string::npos) << nan_run.output;
  EXPECT_FALSE(std::filesystem::exists(out.path() / "nan"));

  const auto budget_run =
      testing::run_isospring("identify " + kExample + " -o " + (out.path() / "budget").string() +
                             " --quiet --max-dofs 10");
  EXPECT_EQ(budget_run.exit_code, 1) << budget_run.output;
  EXPECT_NE(budget_run.output.find("max_dofs 10"), std::string::npos) << budget_run.output;
  EXPECT_FALSE(std::filesystem::exists(out.path() / "budget"));
}

TEST(IdentifyCommand, MarkersOffTheModelFailUnlessDropped) {
  testing::TemporaryFolder out;
  const std::filesystem::path folder = out.path() / "case";
  std::filesystem::create_directories(folder);
  std::filesystem::copy_file(kExample, folder / "case.json");
  std::ifstream in(std::string(ISOSPRING_SOURCE_DIR) + "/examples/identify/markers.csv");
  std::ofstream csv(folder / "markers.csv");
  csv << in.rdbuf() << "L1,0.15,0.02,0.0,0.0\n";  // 5 cm right of the plate
  csv.close();
  const auto failed = testing::run_isospring("identify " + (folder / "case.json").string() +
                                             " -o " + (out.path() / "a").string() + " --quiet");
  EXPECT_EQ(failed.exit_code, 1) << failed.output;
  EXPECT_NE(failed.output.find("row 198"), std::string::npos) << failed.output;
  EXPECT_NE(failed.output.find("--drop-outside"), std::string::npos) << failed.output;
  const auto dropped =
      testing::run_isospring("identify " + (folder / "case.json").string() + " -o " +
                             (out.path() / "b").string() + " --quiet --drop-outside");
  ASSERT_EQ(dropped.exit_code, 0) << dropped.output;
  std::ifstream file(out.path() / "b" / "report.json");
  const nlohmann::json report = nlohmann::json::parse(file);
  ASSERT_EQ(report["markers_dropped"].size(), 1u);
  EXPECT_EQ(report["markers_dropped"][0]["row"], 198);
}

}  // namespace
}  // namespace isospring
