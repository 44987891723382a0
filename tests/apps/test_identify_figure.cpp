// End-to-end: `isospring identify` draws the rms residual before and after the identified
// effects as bars (errors_before_after.png) and links it from report.md, and maps the residual
// per load case in residuals.svg, consistent with residuals.csv and report.json.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <vector>

#include "isospring/io/plot.hpp"
#include "run_program.hpp"

namespace {
// residuals.svg against residuals.csv and report.json: one row of two panels (before, after)
// per load case with as many points as the case has rows in the CSV; the row's colour bar tops
// at the case's largest |r| before, which is report.json's per-case before.max_norm (the "max
// |r| before" of report.md) and the largest residual_before of the CSV, to round-off.
void check_residual_map(const std::filesystem::path& dir) {
  std::ifstream csv(dir / "residuals.csv");
  std::string line;
  std::getline(csv, line);
  std::map<std::string, int> count;
  std::map<std::string, double> largest;
  while (std::getline(csv, line)) {
    std::vector<std::string> cells;
    std::stringstream row(line);
    std::string cell;
    while (std::getline(row, cell, ',')) cells.push_back(cell);
    ASSERT_EQ(cells.size(), 6u) << line;
    ++count[cells[0]];
    largest[cells[0]] = std::max(largest[cells[0]], std::stod(cells[4]));
  }
  ASSERT_FALSE(count.empty());
  std::ifstream report_file(dir / "report.json");
  const auto report = nlohmann::json::parse(report_file);
  ASSERT_EQ(report["load_cases"].size(), count.size());
  double overall = 0.0;
  for (const auto& lc : report["load_cases"]) {
    const std::string id = lc["id"].get<std::string>();
    EXPECT_EQ(lc["markers"].get<int>(), count[id]) << id;
    EXPECT_NEAR(lc["before"]["max_norm"].get<double>(), largest[id], 1e-12 * largest[id]) << id;
    overall = std::max(overall, largest[id]);
  }
  EXPECT_NEAR(report["max_norm_before"].get<double>(), overall, 1e-12 * overall);

  std::ifstream svg_file(dir / "residuals.svg");
  std::stringstream svg_text;
  svg_text << svg_file.rdbuf();
  const std::string svg = svg_text.str();
  const std::regex panel(
      "<g class=\"panel\" data-row=\"([^\"]*)\" data-column=\"([^\"]*)\" "
      "data-points=\"([0-9]+)\">");
  std::map<std::string, std::vector<std::string>> columns;
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), panel); it != std::sregex_iterator();
       ++it) {
    const std::string id = (*it)[1].str();
    columns[id].push_back((*it)[2].str());
    EXPECT_EQ(std::stoi((*it)[3].str()), count[id]) << id;
  }
  ASSERT_EQ(columns.size(), count.size());
  for (const auto& [id, cols] : columns)
    EXPECT_EQ(cols, (std::vector<std::string>{"before", "after"})) << id;
  const std::regex bar(
      "<g class=\"colorbar\" data-row=\"([^\"]*)\" data-min=\"0\" "
      "data-max=\"([^\"]*)\">");
  int bars = 0;
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), bar); it != std::sregex_iterator();
       ++it, ++bars) {
    const std::string id = (*it)[1].str();
    EXPECT_NEAR(std::stod((*it)[2].str()) / largest[id], 1.0, 5e-3) << id;  // printed with %.3g
  }
  EXPECT_EQ(bars, static_cast<int>(count.size()));
  EXPECT_NE(svg.find("|residual| [m]"), std::string::npos);
}
}  // namespace

TEST(IdentifyFigure, BeforeAfterBarsAreWrittenAndLinked) {
  isospring::testing::TemporaryFolder out;
  const auto run = isospring::testing::run_isospring(
      "identify " + std::string(ISOSPRING_SOURCE_DIR) +
      "/examples/identify/plate_hidden_gravity.json -o " + out.path().string() + " --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  check_residual_map(out.path());
  // report.md's error table keeps its six columns: the "|r|" in its header is escaped.
  {
    std::ifstream md_file(out.path() / "report.md");
    std::string line;
    bool found = false;
    while (std::getline(md_file, line))
      if (line.rfind("| load case | markers |", 0) == 0) {
        found = true;
        const std::string unescaped = std::regex_replace(line, std::regex("\\\\\\|"), "");
        EXPECT_EQ(std::count(unescaped.begin(), unescaped.end(), '|'), 7) << line;
      }
    EXPECT_TRUE(found);
  }
  if (!isospring::io::gnuplot_available()) GTEST_SKIP() << "gnuplot not installed";
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
