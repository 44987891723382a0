// `isospring identify` must never blame physics for the model's own discretisation error.
//
// Data from an independent solver (tests/common/calculix_dataset.hpp): CalculiX, C3D20R on a
// 30 x 6 x 6 mesh, solves a clamped 100 x 20 x 20 mm cantilever with the TRUE E (the case declares
// 20 % less) under three load cases; 0.2 % noise on surface markers. The case file's own model is
// deliberately coarse (degree 2, 10 x 2 x 2 elements): its error at the markers is several times
// the noise. With the discretisation check off, the loop "explains" that error by effects that are
// not in the data; with it on, the loop refines the reference (degree elevation from the case's
// exact geometry) and adds nothing; with a DOF budget too small to refine, it widens its F-tests
// instead and still adds nothing. A second data set with real self-weight shows that the check
// does not hide a real effect. Skipped when ccx is not on PATH.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "calculix_dataset.hpp"
#include "isospring/io/case_file.hpp"
#include "run_program.hpp"

namespace isospring {
namespace {

namespace fs = std::filesystem;

constexpr double kTrueModulus = 1e7, kDeclaredModulus = 0.8e7;
constexpr double kNoiseFraction = 2e-3;  // of the largest displacement, as in the data

nlohmann::json cantilever_case(double modulus, int elements_along, bool gravity) {
  nlohmann::json load_cases = nlohmann::json::array();
  load_cases.push_back(
      {{"id", "tip_down"}, {"tractions", {{{"side", "u1"}, {"value", {0.0, 0.0, -2000.0}}}}}});
  load_cases.push_back(
      {{"id", "tip_side"}, {"tractions", {{{"side", "u1"}, {"value", {0.0, 1500.0, 0.0}}}}}});
  load_cases.push_back(
      {{"id", "pull"}, {"tractions", {{{"side", "u1"}, {"value", {20000.0, 0.0, 0.0}}}}}});
  if (gravity)
    for (auto& load : load_cases) load["gravity"] = {0.0, 0.0, -9.81};
  return {{"schema_version", 1},
          {"name", "cantilever_discretization"},
          {"units", "SI"},
          {"geometry", {{"type", "box"}, {"size", {0.1, 0.02, 0.02}}}},
          {"discretization", {{"degree", {2, 2, 2}}, {"elements", {elements_along, 2, 2}}}},
          {"material", {{"E", modulus}, {"nu", 0.3}, {"density", 1000.0}}},
          {"boundary", {{{"side", "u0"}, {"fix", {"x", "y", "z"}}}}},
          {"load_cases", load_cases}};
}

// ccx data of the true cantilever (30 x 6 x 6 C3D20R) on the top and one side face, x > 5 mm.
testing::CalculixDataset cantilever_data(const fs::path& folder, bool gravity, unsigned seed) {
  nlohmann::json truth_json = cantilever_case(kTrueModulus, 30, gravity);
  truth_json["discretization"]["elements"] = {30, 6, 6};
  const io::Case truth = io::build_case_from_json(truth_json, folder / "truth.json");
  testing::CalculixDatasetSpec spec;
  spec.truth = truth.problem;
  spec.is_marker = [](const Eigen::Vector3d& x) {
    return x.x() > 0.005 && (std::abs(x.z() - 0.02) < 1e-9 || std::abs(x.y()) < 1e-9);
  };
  spec.stride = 7;
  spec.noise_fraction = kNoiseFraction;
  spec.seed = seed;
  return testing::make_calculix_dataset(spec, folder / "ccx");
}

// Writes the declared (coarse, E 20 % low) case beside markers.csv; linear candidates only: the
// deflections are 2 % of the length, where large-deformation effects are below the noise, and
// the geometric_nonlinearity candidate is tested on its own (test_identify_nonlinear.cpp).
fs::path write_declared_case(const fs::path& folder, const testing::CalculixDataset& data) {
  testing::write_markers_csv(folder / "markers.csv", data.markers);
  nlohmann::json c = cantilever_case(kDeclaredModulus, 10, false);
  c["measurements"] = {
      {"file", "markers.csv"},
      {"effects",
       {"gravity", "support_compliance", "stiffness_gradient", "rigid_offset", "load_scale"}}};
  std::ofstream(folder / "case.json") << c.dump(2);
  return folder / "case.json";
}

nlohmann::json run_identify(const fs::path& case_file, const fs::path& out,
                            const std::string& flags) {
  const auto run = testing::run_isospring("identify " + case_file.string() + " -o " + out.string() +
                                          " --quiet " + flags);
  EXPECT_EQ(run.exit_code, 0) << run.output;
  std::ifstream file(out / "report.json");
  if (!file) return {};
  return nlohmann::json::parse(file);
}

double fitted_modulus(const nlohmann::json& report) {
  for (const auto& p : report["parameters"])
    if (p["name"] == "E") return p["value"].get<double>();
  return 0.0;
}

TEST(IdentifyDiscretization, CoarseCaseIsRefinedInsteadOfGainingEffects) {
  if (!testing::calculix_available())
    GTEST_SKIP() << "ccx (CalculiX, Debian package calculix-ccx) is not on PATH";
  testing::TemporaryFolder folder;
  const testing::CalculixDataset data = cantilever_data(folder.path(), false, 7);
  ASSERT_TRUE(data.error.empty()) << data.error;
  ASSERT_GT(data.markers.size(), 400u);
  const fs::path case_file = write_declared_case(folder.path(), data);

  // Without the check the loop blames physics for the coarse model's error: this is what the
  // test guards against, so it must be visible here (or the data would not test anything).
  const nlohmann::json unchecked =
      run_identify(case_file, folder.path() / "unchecked", "--no-discretization-check");
  ASSERT_FALSE(unchecked.empty());
  EXPECT_FALSE(unchecked["effects_added"].empty())
      << "the coarse model fits the data without effects: the data no longer test the check";
  EXPECT_EQ(unchecked["discretization"]["done"], false);

  const nlohmann::json checked = run_identify(case_file, folder.path() / "checked", "");
  ASSERT_FALSE(checked.empty());
  const nlohmann::json& disc = checked["discretization"];
  EXPECT_EQ(checked["effects_added"], nlohmann::json::array()) << disc.dump(1);
  EXPECT_EQ(disc["done"], true);
  EXPECT_EQ(disc["within_target"], true);
  EXPECT_GE(disc["chosen_level"].get<int>(), 1) << disc.dump(1);
  const auto& levels = disc["levels"];
  // The case's own level misses the target (that is the premise), the chosen one meets it.
  EXPECT_GT(levels[0]["marker_error_rms"].get<double>(), disc["target"].get<double>());
  const auto& used = levels[disc["chosen_level"].get<size_t>()];
  EXPECT_LE(used["marker_error_rms"].get<double>(), disc["target"].get<double>());
  // A finer level estimated it, or its own error extrapolated from a convergence ratio is at
  // most half the target (the next, largest solve skipped). A level between two of the ladder's
  // is listed last and estimated against the finest.
  const bool between =
      used["discretization"].get<std::string>().find("(between levels") != std::string::npos;
  if (between) {
    EXPECT_NE(used["estimate"].get<std::string>().find("difference to level"), std::string::npos)
        << disc.dump(1);
  }
  if (!between && levels.size() == disc["chosen_level"].get<size_t>() + 1) {
    EXPECT_NE(used["estimate"].get<std::string>().find("extrapolated with ratio"),
              std::string::npos)
        << disc.dump(1);
    EXPECT_LE(used["marker_error_rms"].get<double>(), 0.5 * disc["target"].get<double>());
  }
  // The noise the check compared with is the data's (estimated, not given): within 20 %.
  EXPECT_NEAR(disc["noise"].get<double>(), data.noise_sigma, 0.2 * data.noise_sigma);
  // E within 0.5 % of the truth (ccx's own error and the noise are far below that); the residual
  // is the noise.
  EXPECT_NEAR(fitted_modulus(checked), kTrueModulus, 5e-3 * kTrueModulus);
  EXPECT_LT(checked["rms_after"].get<double>(), 1.3 * data.noise_sigma);

  // A DOF budget that allows one level only, too coarse for the data: the F-tests are widened by
  // that level's estimated error, and still nothing is added.
  const int level1_dofs = levels[1]["dofs"].get<int>();
  const nlohmann::json widened = run_identify(case_file, folder.path() / "widened",
                                              "--max-dofs " + std::to_string(level1_dofs));
  ASSERT_FALSE(widened.empty());
  EXPECT_EQ(widened["effects_added"], nlohmann::json::array());
  EXPECT_EQ(widened["discretization"]["budget_exhausted"], true);
  EXPECT_EQ(widened["discretization"]["within_target"], false);
  EXPECT_GT(widened["discretization"]["f_test_allowance"].get<double>(), 0.0);
  const std::string md = testing::file_contents((folder.path() / "widened" / "report.md").string());
  EXPECT_NE(md.find("widened every F-test"), std::string::npos);
}

TEST(IdentifyDiscretization, RealSelfWeightIsStillFound) {
  if (!testing::calculix_available())
    GTEST_SKIP() << "ccx (CalculiX, Debian package calculix-ccx) is not on PATH";
  testing::TemporaryFolder folder;
  const testing::CalculixDataset data = cantilever_data(folder.path(), true, 11);
  ASSERT_TRUE(data.error.empty()) << data.error;
  const fs::path case_file = write_declared_case(folder.path(), data);
  const nlohmann::json report = run_identify(case_file, folder.path() / "out", "");
  ASSERT_FALSE(report.empty());
  EXPECT_EQ(report["effects_added"], nlohmann::json({"gravity"}));
  for (const auto& p : report["parameters"])
    if (p["name"] == "gz") {
      EXPECT_NEAR(p["value"].get<double>(), -9.81, 0.02 * 9.81);
    }
  EXPECT_NEAR(fitted_modulus(report), kTrueModulus, 5e-3 * kTrueModulus);
  EXPECT_LT(report["rms_after"].get<double>(), 1.3 * data.noise_sigma);
}

}  // namespace
}  // namespace isospring
