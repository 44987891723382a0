// End-to-end: the file-writing commands print nothing with --quiet and still write their file
// (the same file as without it).
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "run_program.hpp"

using isospring::testing::example;
using isospring::testing::file_contents;
using isospring::testing::run_isospring;
using isospring::testing::TemporaryFolder;

// (export-step: FileReports.ExportsReportWhatTheyWrote.)
TEST(Quiet, ImportAndRefineWriteSilently) {
  TemporaryFolder out;
  const std::vector<std::pair<std::string, std::string>> commands{
      {"import " + example("cad/block.step"), "block.json"},
      {"refine " + example("patches/quarter_annulus.json") + " --h 2", "refined.json"}};
  for (const auto& [command, file] : commands) {
    const auto loud = run_isospring(command + " -o " + (out / ("loud_" + file)));
    ASSERT_EQ(loud.exit_code, 0) << loud.output;
    EXPECT_NE(loud.output.find("wrote "), std::string::npos) << command;
    const auto quiet = run_isospring(command + " -o " + (out / file) + " --quiet");
    ASSERT_EQ(quiet.exit_code, 0) << quiet.output;
    EXPECT_EQ(quiet.output, "") << command;
    ASSERT_FALSE(file_contents(out / file).empty()) << command;
    EXPECT_EQ(file_contents(out / file), file_contents(out / ("loud_" + file))) << command;
  }
}

// OpenCascade's IGES reader announces "Total number of loaded entities" on stdout; reading a part
// (import -q, info --json) must not, or scripts parsing the JSON break. No IGES part is shipped,
// so one is written from a shipped patch file first.
TEST(Quiet, ReadingAnIgesPartPrintsNothing) {
  TemporaryFolder out;
  auto run = run_isospring("export-step " + example("patches/quarter_annulus.json") + " -o " +
                           (out / "annulus.igs") + " -q");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  run = run_isospring("import " + (out / "annulus.igs") + " -o " + (out / "annulus.json") + " -q");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(run.output, "");
  run = run_isospring("info " + (out / "annulus.igs") + " --json");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  // The whole output (stdout and stderr) is one JSON document: nothing printed around it.
  nlohmann::json info;
  ASSERT_NO_THROW(info = nlohmann::json::parse(run.output)) << run.output;
  EXPECT_EQ(info["kind"], "cad");
}
