// End-to-end: `isospring info`, `refine` and `eval` on shipped patch files, their numbers and
// their exit codes (0 ok, 1 bad input, 2 usage).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "isospring/io/patch_file.hpp"
#include "run_program.hpp"

using isospring::testing::run_isospring;
using isospring::testing::run_isospring_with_environment;
using isospring::testing::TemporaryFolder;

namespace {
const std::string kAnnulus =
    std::string(ISOSPRING_SOURCE_DIR) + "/examples/patches/quarter_annulus.json";

void write(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
}
}  // namespace

TEST(CliKernel, VersionAndHelp) {
  EXPECT_EQ(run_isospring("--version").exit_code, 0);
  const auto help = run_isospring("--help");
  EXPECT_EQ(help.exit_code, 0);
  for (const char* command : {"info", "refine", "eval"})
    EXPECT_NE(help.output.find(command), std::string::npos) << command;
  for (const char* command : {"info", "refine", "eval"})
    EXPECT_EQ(run_isospring(std::string(command) + " --help").exit_code, 0) << command;
}

TEST(CliKernel, InfoDescribesThePatch) {
  const auto result = run_isospring("info " + kAnnulus);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("parametric dimension 2, physical dimension 2, rational"),
            std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("u: degree 2, 1 elements, knots (value^multiplicity): 0^3 1^3"),
            std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("control points: 6 (3 x 2)"), std::string::npos) << result.output;
}

TEST(CliKernel, RefineKeepsTheGeometryExact) {
  TemporaryFolder folder;
  const auto result = run_isospring("refine " + kAnnulus + " -o " + folder / "fine.json" +
                                    " --elevate 1 --insert u=0.3,0.3 --h 3");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const auto fine = isospring::io::read_patch_file(folder / "fine.json").at(0);
  EXPECT_EQ(fine.degree(0), 3);
  EXPECT_EQ(fine.degree(1), 2);
  EXPECT_EQ(fine.knots(0).multiplicity(0.3), 2);
  // 1 element elevated, 0.3 inserted (2 elements), each split in 3 -> 6 elements along u.
  EXPECT_EQ(fine.knots(0).num_elements(), 6);
  EXPECT_EQ(fine.knots(1).num_elements(), 3);
  for (int q = 0; q <= 100; ++q) {
    const double u = q / 100.0;
    EXPECT_NEAR(fine.point({u, 0.0, 0}).norm(), 1.0, 1e-14);
    EXPECT_NEAR(fine.point({u, 1.0, 0}).norm(), 2.0, 2e-14);
  }
}

TEST(CliKernel, EvalPrintsPointsAndDerivatives) {
  const auto result = run_isospring("eval " + kAnnulus + " --at 0.5,0 --at 0,1 --derivs");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  std::istringstream lines(result.output);
  std::string label;
  double x = 0, y = 0, z = 0;
  lines >> label >> x >> y >> z;
  EXPECT_EQ(label, "0.5,0:");
  EXPECT_NEAR(x, std::sqrt(0.5), 1e-15);  // the arc's midpoint at 45 degrees
  EXPECT_NEAR(y, std::sqrt(0.5), 1e-15);
  EXPECT_NE(result.output.find("0,1: 2 0 0"), std::string::npos) << result.output;
}

TEST(CliKernel, BadInputExitsWithOneAndNamesTheField) {
  TemporaryFolder folder;
  struct Case {
    std::string json, expected;
  };
  const std::vector<Case> cases = {
      {R"({"patches":[{"degrees":[2],"knots":[[0,0,0,0.7,0.5,1,1,1]],"control_points":[[0,0,0],[1,0,0],[2,0,0],[3,0,0],[4,0,0]]}]})",
       "patches[0].knots[0]: knots must not decrease"},
      {R"({"patches":[{"degrees":[2],"knots":[[0,0,0.5,1,1,1]],"control_points":[[0,0,0],[1,0,0],[2,0,0]]}]})",
       "patches[0].knots[0]: is not clamped"},
      {R"({"patches":[{"degrees":[1],"knots":[[0,0,0.5,0.5,1,1]],"control_points":[[0,0,0],[1,0,0],[2,0,0],[3,0,0]]}]})",
       "multiplicity above the degree"},
      {R"({"patches":[{"degrees":[1],"knots":[[0,0,1,1]],"control_points":[[0,0,0],[1,0,0],[2,0,0]]}]})",
       "patches[0].control_points has 3 points, but the knots give 2"},
      {R"({"patches":[{"degrees":[1],"knots":[[0,0,1,1]],"control_points":[[0,0,0],[1,0,0]],"weights":[1,0]}]})",
       "patches[0].weights[1] = 0.000000 must be > 0"},
      {R"({"patches":[{"degrees":[1],"knots":[[0,0,1,1]],"control_points":[[0,0,0],[1,0]]}]})",
       "patches[0].control_points[1] has 2 coordinates; always give 3"},
      {R"({"patches":[{"degrees":[1],"knots":[[0,0,1,1]],"control_points":[[0,0,0],[1,0,0]],"weight":[1,1]}]})",
       "patches[0].weight: unknown field"},
      {R"({"patches":[{"degrees":[0],"knots":[[0,1]],"control_points":[[0,0,0]]}]})",
       "patches[0].degrees[0] must be an integer >= 1, got 0"},
      {R"({"patches":[{"degrees":[1],"knots":[[0,0,"1",1]],"control_points":[[0,0,0],[1,0,0]]}]})",
       "patches[0].knots[0][2] must be a number, got string"},
      {R"({"patches":[{"degrees":[1],"knots":[[0,0,1,1]],"control_points":[[0,0,0],[1,0,0]]}],)",
       "not valid JSON"},
  };
  for (size_t i = 0; i < cases.size(); ++i) {
    const std::string path = folder / ("bad" + std::to_string(i) + ".json");
    write(path, cases[i].json);
    const auto result = run_isospring("info " + path);
    EXPECT_EQ(result.exit_code, 1) << result.output;
    EXPECT_NE(result.output.find(cases[i].expected), std::string::npos) << result.output;
    EXPECT_NE(result.output.find(path), std::string::npos) << "message must name the file";
  }
  // NaN cannot be written in JSON; a huge exponent overflows to inf in the parser: rejected too.
  write(
      folder / "inf.json",
      R"({"patches":[{"degrees":[1],"knots":[[0,0,1,1]],"control_points":[[0,0,0],[1e999,0,0]]}]})");
  EXPECT_EQ(run_isospring("info " + folder / "inf.json").exit_code, 1);
}

TEST(CliKernel, UsageErrorsExitWithTwoAndNothingIsWritten) {
  TemporaryFolder folder;
  EXPECT_EQ(run_isospring("").exit_code, 2);
  EXPECT_EQ(run_isospring("frobnicate").exit_code, 2);
  EXPECT_EQ(run_isospring("refine " + kAnnulus).exit_code, 2);  // -o missing
  EXPECT_EQ(run_isospring("refine " + kAnnulus + " -o " + folder / "x.json" + " --h -2").exit_code,
            2);
  // Bad values that only the computation can judge are bad input (1), and leave no file.
  const auto result =
      run_isospring("refine " + kAnnulus + " -o " + folder / "y.json" + " --insert u=1.5");
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_FALSE(std::filesystem::exists(folder / "y.json"));
  EXPECT_EQ(run_isospring("eval " + kAnnulus + " --at 0.5").exit_code, 1);
  EXPECT_EQ(run_isospring("eval " + kAnnulus + " --at 0.5,2").exit_code, 1);
}

namespace {
// libgomp's own report of the spin count it started with (OMP_DISPLAY_ENV=verbose): the last one
// printed, i.e. that of the process that ran the command.
std::string started_spin_count(const std::string& environment) {
  const auto result = run_isospring_with_environment(environment, "--version");
  EXPECT_EQ(result.exit_code, 0) << result.output;
  const std::string& output = result.output;
  const std::string key = "GOMP_SPINCOUNT = '";
  const size_t at = output.rfind(key);
  if (at == std::string::npos) return "not reported: " + output;
  const size_t begin = at + key.size();
  return output.substr(begin, output.find('\'', begin) - begin);
}
}  // namespace

TEST(CliKernel, OpenMpThreadsSleepInsteadOfSpinningUnlessTheUserChose) {
  const std::string unset = "env -u OMP_WAIT_POLICY -u GOMP_SPINCOUNT OMP_DISPLAY_ENV=verbose";
  EXPECT_EQ(started_spin_count(unset), "0");  // passive
  EXPECT_NE(started_spin_count(unset + " OMP_WAIT_POLICY=active"), "0");
  EXPECT_EQ(started_spin_count(unset + " GOMP_SPINCOUNT=1234"), "1234");
}
