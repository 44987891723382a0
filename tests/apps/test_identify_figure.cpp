// End-to-end: `isospring identify` draws the rms residual before and after the identified
// effects as bars (errors_before_after.png) and links it from report.md.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "isospring/io/plot.hpp"
#include "run_program.hpp"

TEST(IdentifyFigure, BeforeAfterBarsAreWrittenAndLinked) {
  if (!isospring::io::gnuplot_available()) GTEST_SKIP() << "gnuplot not installed";
  isospring::testing::TemporaryFolder out;
  const auto run = isospring::testing::run_isospring(
      "identify " + std::string(ISOSPRING_SOURCE_DIR) +
      "/examples/identify/plate_hidden_gravity.json -o " + out.path().string() + " --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  std::ifstream png(out.path() / "errors_before_after.png", std::ios::binary);
  char magic[8] = {};
  png.read(magic, 8);
  EXPECT_EQ(std::string(magic, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  EXPECT_GT(std::filesystem::file_size(out.path() / "errors_before_after.png"), 5000u);
  std::ifstream md_file(out.path() / "report.md");
  std::stringstream md;
  md << md_file.rdbuf();
  EXPECT_NE(md.str().find("](errors_before_after.png)"), std::string::npos);
  // The bars show the report's numbers: the hidden gravity removes most of the residual.
  std::ifstream report_file(out.path() / "report.json");
  const auto report = nlohmann::json::parse(report_file);
  EXPECT_LT(report["rms_after"].get<double>(), 0.1 * report["rms_before"].get<double>());
}
