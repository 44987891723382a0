// End-to-end: the file-writing commands print nothing with --quiet and still write their file
// (the same file as without it).
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "run_program.hpp"

using isospring::testing::run_isospring;
using isospring::testing::TemporaryFolder;

namespace {
std::string example(const std::string& name) {
  return std::string(ISOSPRING_SOURCE_DIR) + "/examples/" + name;
}

std::string contents(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}
}  // namespace

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
    ASSERT_FALSE(contents(out / file).empty()) << command;
    EXPECT_EQ(contents(out / file), contents(out / ("loud_" + file))) << command;
  }
}
