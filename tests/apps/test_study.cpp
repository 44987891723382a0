// End-to-end: `isospring study` on the Kirsch plate converges at the theoretical rates
// (benchmarks.md: L2 O(h^(p+1)), energy O(h^p)) and writes its tables and plot.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "run_program.hpp"

using isospring::testing::run_isospring;
using isospring::testing::TemporaryFolder;

TEST(Study, KirschPlateConvergesAtTheExpectedRates) {
  TemporaryFolder out;
  const auto result = run_isospring("study " + std::string(ISOSPRING_SOURCE_DIR) +
                                    "/examples/kirsch_plate.json -o " + out.path().string() +
                                    " --levels 4 --degrees 2 --quiet");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  std::ifstream in(out / "report.json");
  const auto report = nlohmann::json::parse(in);
  ASSERT_EQ(report["degrees"].size(), 1u);
  const auto& levels = report["degrees"][0]["levels"];
  ASSERT_EQ(levels.size(), 4u);
  // Measured on the last pair: L2 3.29, energy 1.99 (p = 2); pre-asymptotic levels are lower.
  EXPECT_GE(levels[3]["rate"].get<double>(), 2.9);
  EXPECT_GE(levels[3]["energy_rate"].get<double>(), 1.9);
  EXPECT_LT(levels[3]["relative_l2_error"].get<double>(), 1e-5);
  EXPECT_EQ(levels[0]["dofs"], 120);  // 2 x (8 + 2) x (4 + 2)
  std::ifstream csv(out / "study.csv");
  int lines = 0;
  for (std::string line; std::getline(csv, line);) ++lines;
  EXPECT_EQ(lines, 5);
  if (std::system("command -v gnuplot > /dev/null 2>&1") == 0) {
    EXPECT_TRUE(std::filesystem::exists(out / "convergence.png"));
  }
  EXPECT_EQ(
      run_isospring("study " + std::string(ISOSPRING_SOURCE_DIR) +
                    "/examples/kirsch_plate.json -o " + out.path().string() + " --degrees 1 -q")
          .exit_code,
      1);  // degree below the exact geometry's
}
