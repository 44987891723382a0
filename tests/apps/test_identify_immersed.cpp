// End-to-end: `isospring identify` on immersed cases, against data nobody in the project's
// immersed code produced: CalculiX on a gmsh mesh of the same STEP file (the rounded bracket,
// second-order tetrahedra; scripts/calculix_immersed_identify.py wrote the markers and
// truth.json), plus Gaussian noise of 0.2 % of the largest marker displacement.
// Both cases use the default background grid (10 x 5 x 5 quadratic cells, 1,260 DOFs), whose own
// error at the markers is several times the noise (a spurious load_scale of 4.5 % was added on it
// without a discretisation check): the check must climb the ladder of finer grids.
// - markers_weight.csv carries the part's own weight (g = 9.81 m/s^2 along -z), which the case
//   does not declare: the loop must add gravity and nothing else, with g within 3 standard
//   errors of the truth, and leave a residual within 1.3 x the noise.
// - markers_clean.csv has the declared loads alone: the loop must add nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "run_program.hpp"

using isospring::testing::example;
using isospring::testing::read_json;
using isospring::testing::run_isospring;
using isospring::testing::TemporaryFolder;
using nlohmann::json;

namespace {

double truth_noise(const std::string& dataset) {
  return read_json(
             example("immersed/identify_bracket/truth.json"))["datasets"][dataset]["noise_sigma_m"]
      .get<double>();
}

// The discretisation check ran on the default grid, refused it and chose a finer one.
void expect_climbed(const json& check) {
  ASSERT_TRUE(check["done"].get<bool>()) << check;
  ASSERT_GE(check["levels"].size(), 3u) << check;
  EXPECT_EQ(check["levels"][0]["dofs"], 1260) << check;  // the case's own grid
  EXPECT_GT(check["levels"][0]["error_over_noise"].get<double>(), 1.0 / 3.0) << check;
  EXPECT_GE(check["chosen_level"].get<int>(), 1) << check;
  for (const auto& level : check["levels"]) EXPECT_LE(level["dofs"].get<int>(), 25000);
  const json& chosen = check["levels"][check["chosen_level"].get<size_t>()];
  std::printf("  discretisation check: chosen %s, %d DOFs, %.3f x the noise, within target %d\n",
              chosen["discretization"].get<std::string>().c_str(), chosen["dofs"].get<int>(),
              chosen["error_over_noise"].get<double>(), check["within_target"].get<bool>());
}

TEST(IdentifyImmersed, NamesTheUndeclaredSelfWeightInCalculixData) {
  TemporaryFolder out;
  const auto run =
      run_isospring("identify " + example("immersed/identify_bracket/case_weight.json") + " -o " +
                    (out / "id") + " --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const json report = read_json(out.path() / "id" / "report.json");
  EXPECT_EQ(report["effects_added"], json::array({"gravity"})) << report["effects_added"];
  const double sigma = truth_noise("weight");
  EXPECT_LE(report["rms_after"].get<double>(), 1.3 * sigma);
  EXPECT_GT(report["rms_before"].get<double>(), 3.0 * sigma);  // the weight was visible
  const double truth[3] = {0.0, 0.0, -9.81};
  int seen = 0;
  for (const auto& p : report["parameters"]) {
    if (p["effect"] != "gravity") continue;
    const double value = p["value"].get<double>(), error = p["standard_error"].get<double>();
    EXPECT_LT(std::abs(value - truth[seen]), std::max(3.0 * error, 0.0))
        << p["name"] << " = " << value << " +- " << error;
    ++seen;
  }
  EXPECT_EQ(seen, 3);
  expect_climbed(report["discretization"]);
  EXPECT_TRUE(std::filesystem::exists(out.path() / "id" / "report.md"));
  EXPECT_TRUE(std::filesystem::exists(out.path() / "id" / "markers_side_after.vtp"));
  EXPECT_FALSE(std::filesystem::exists(out.path() / "id" / "model.json"));
  std::printf(
      "immersed identify (CalculiX data, hidden weight): rms %.3e -> %.3e m, noise %.3e m\n",
      report["rms_before"].get<double>(), report["rms_after"].get<double>(), sigma);
}

TEST(IdentifyImmersed, AddsNothingToCleanCalculixData) {
  TemporaryFolder out;
  const auto run =
      run_isospring("identify " + example("immersed/identify_bracket/case_clean.json") + " -o " +
                    (out / "id") + " --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const json report = read_json(out.path() / "id" / "report.json");
  EXPECT_TRUE(report["effects_added"].empty()) << report["effects_added"];
  expect_climbed(report["discretization"]);
  const double sigma = truth_noise("clean");
  EXPECT_LE(report["rms_after"].get<double>(), 1.3 * sigma);
  std::printf("immersed identify (CalculiX data, clean): rms %.3e m, noise %.3e m\n",
              report["rms_after"].get<double>(), sigma);
}

}  // namespace
