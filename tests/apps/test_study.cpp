// End-to-end: `isospring study` on the Kirsch plate converges at the theoretical rates
// (benchmarks.md: L2 O(h^(p+1)), energy O(h^p)) and writes its tables and plot; Richardson
// extrapolation of a point displacement recovers known exact values with and without an
// analytic solution in the case.
#include <gtest/gtest.h>

#include <cmath>
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

namespace {

nlohmann::json read_report(const std::filesystem::path& folder) {
  std::ifstream in(folder / "report.json");
  return nlohmann::json::parse(in);
}

// Least-squares slope of log(error) against log(h) over all given levels.
double slope(const std::vector<double>& h, const std::vector<double>& error) {
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (size_t i = 0; i < h.size(); ++i) {
    const double x = std::log(h[i]), y = std::log(error[i]);
    n += 1, sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

}  // namespace

// Timoshenko cantilever (examples/timoshenko_beam.json: L = 10, D = 2, P = 1, E = 1e5, nu = 0.3),
// p = 2 (p >= 3 contains the cubic exact field): tip deflection at the beam axis.
TEST(Study, RichardsonRecoversTheTimoshenkoTipDeflection) {
  TemporaryFolder out;
  const auto result = run_isospring(
      "study " + std::string(ISOSPRING_SOURCE_DIR) + "/examples/timoshenko_beam.json -o " +
      out.path().string() +
      " --levels 4 --degrees 2 --quantity displacement --point 0:1,0.5 --component y -q");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const auto report = read_report(out.path());
  // benchmarks.md: uy(L, 0) = -P / (6 E I) [(4 + 5 nu) D^2 L / 4 + 2 L^3], I = D^3 / 12.
  const double L = 10, D = 2, P = 1, E = 1e5, nu = 0.3, I = D * D * D / 12;
  const double exact = -P / (6 * E * I) * ((4 + 5 * nu) * D * D * L / 4 + 2 * L * L * L);
  ASSERT_TRUE(report.contains("exact_quantity"));
  EXPECT_NEAR(report["exact_quantity"].get<double>(), exact, 1e-14 * std::abs(exact));
  const auto& degree = report["degrees"][0];
  const auto& r = degree["richardson"];
  ASSERT_EQ(r["status"], "extrapolated") << r.dump();
  std::vector<double> h, error;
  for (const auto& level : degree["levels"]) {
    h.push_back(level["h"].get<double>());
    error.push_back(std::abs(level["quantity"].get<double>() - exact));
    EXPECT_NEAR(level["quantity_exact_error"].get<double>(), error.back() / std::abs(exact), 1e-12);
  }
  // The order Richardson observes from differences only, against the order of the true errors
  // over the same three levels (measured 3.785 and 3.77).
  const double true_order = slope({h[1], h[2], h[3]}, {error[1], error[2], error[3]});
  std::printf(
      "Timoshenko tip p=2: Richardson order %.4f (true %.4f), extrapolated %.15g (exact "
      "%.15g), finest error %.3e, estimate %.3e\n",
      r["order"].get<double>(), true_order, r["value"].get<double>(), exact, error[3],
      r["finest_error_estimate"].get<double>());
  EXPECT_NEAR(r["order"].get<double>(), true_order, 0.1);
  // The extrapolated value is far closer than the finest level (measured 79 times) and the
  // finest level's error estimate is right to 1.2 % (10 % allowed).
  EXPECT_LT(std::abs(r["value"].get<double>() - exact), 0.05 * error[3]);
  EXPECT_NEAR(r["finest_error_estimate"].get<double>(), error[3], 0.1 * error[3]);
}

// Without "analytic" the quantity's errors are against the Richardson value. The Lame cylinder
// with its analytic block removed: the inner radial displacement at (Ri, 0) is known,
// u_r(Ri) = P Ri^2 / (E' (Ro^2 - Ri^2)) ((1 - nu') Ri + (1 + nu') Ro^2 / Ri) with plane-strain
// E' = E / (1 - nu^2), nu' = nu / (1 - nu). It converges at 2p (nodal superconvergence of this
// effectively 1D radial problem; measured 4.03, 4.02, 4.02 per halving at p = 2).
TEST(Study, WithoutAnalyticSolutionErrorsAreAgainstTheRichardsonValue) {
  TemporaryFolder out;
  nlohmann::json c;
  {
    std::ifstream in(std::string(ISOSPRING_SOURCE_DIR) + "/examples/lame_cylinder.json");
    c = nlohmann::json::parse(in);
  }
  c.erase("analytic");
  const std::filesystem::path case_file = out.path() / "lame_without_analytic.json";
  std::ofstream(case_file) << c.dump(2);
  const auto result =
      run_isospring("study " + case_file.string() + " -o " + (out.path() / "study").string() +
                    " --levels 4 --degrees 2 --quantity displacement --point 0:0,0 "
                    "--component x -q");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const auto report = read_report(out.path() / "study");
  EXPECT_EQ(report["reference"], "Richardson extrapolation of the quantity (else finest level)");
  EXPECT_FALSE(report.contains("exact_quantity"));
  const double E = 1e5, nu = 0.3, P = 100, ri = 1, ro = 2;
  const double e = E / (1 - nu * nu), n = nu / (1 - nu);
  const double exact =
      P * ri * ri / (e * (ro * ro - ri * ri)) * ((1 - n) * ri + (1 + n) * ro * ro / ri);
  const auto& degree = report["degrees"][0];
  const auto& r = degree["richardson"];
  ASSERT_EQ(r["status"], "extrapolated") << r.dump();
  const double value = r["value"].get<double>();
  const double finest = degree["levels"][3]["quantity"].get<double>();
  std::printf(
      "Lame inner u_r p=2: Richardson order %.4f, extrapolated %.15g (exact %.15g), "
      "finest error %.3e\n",
      r["order"].get<double>(), value, exact, std::abs(finest - exact) / exact);
  EXPECT_NEAR(r["order"].get<double>(), 4.0, 0.05);
  // Measured 1.3e-10 relative against 1.7e-8 for the finest level.
  EXPECT_LT(std::abs(value - exact), 1e-9 * exact);
  EXPECT_GT(std::abs(finest - exact), 50 * std::abs(value - exact));
  for (const auto& level : degree["levels"]) {
    EXPECT_TRUE(level["relative_l2_error"].is_null());
    EXPECT_NEAR(level["quantity_error"].get<double>(),
                std::abs(level["quantity"].get<double>() - value) / value, 1e-15);
  }
  // Without an analytic solution the fitted rate is the quantity's (last three levels).
  EXPECT_NEAR(degree["fitted_rate"].get<double>(), 4.0, 0.05);

  // The default quantity, the strain energy, equals half the work of the pressure on the inner
  // quarter circle: U = 1/2 P u_r(Ri) (pi / 2) Ri (thickness 1). Energy converges at 2p
  // (measured order 4.006, extrapolated value within 3.4e-11 against 1.7e-8 for the finest).
  const auto energy_run =
      run_isospring("study " + case_file.string() + " -o " + (out.path() / "energy").string() +
                    " --levels 4 --degrees 2 -q");
  ASSERT_EQ(energy_run.exit_code, 0) << energy_run.output;
  const auto energy_report = read_report(out.path() / "energy");
  EXPECT_EQ(energy_report["quantity"], "strain energy");
  const double exact_energy = 0.5 * P * exact * M_PI / 2 * ri;
  const auto& re = energy_report["degrees"][0]["richardson"];
  ASSERT_EQ(re["status"], "extrapolated") << re.dump();
  EXPECT_NEAR(re["order"].get<double>(), 4.0, 0.05);
  EXPECT_NEAR(re["value"].get<double>(), exact_energy, 1e-9 * exact_energy);
  EXPECT_NEAR(energy_report["degrees"][0]["levels"][3]["quantity"].get<double>(), exact_energy,
              1e-7 * exact_energy);
}

TEST(Study, BadQuantityOptionsAreInputErrors) {
  TemporaryFolder out;
  const std::string base = "study " + std::string(ISOSPRING_SOURCE_DIR) +
                           "/examples/lame_cylinder.json -o " + out.path().string() +
                           " --levels 1 -q ";
  for (const std::string bad :
       {"--quantity stress", "--quantity displacement", "--quantity displacement --point 1:0,0",
        "--quantity displacement --point 0:0,1.5", "--quantity displacement --point 0:0",
        "--quantity displacement --point 0:0,0 --component z", "--point 0:0,0"}) {
    const auto result = run_isospring(base + bad);
    EXPECT_EQ(result.exit_code, 1) << bad << ": " << result.output;
  }
  const auto result = run_isospring(base + "--quantity displacement");
  EXPECT_NE(result.output.find("needs --point"), std::string::npos) << result.output;
}
