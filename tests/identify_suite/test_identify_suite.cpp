// The unseen-data suite: `isospring identify` on every dataset of
// examples/identify_suite must add exactly the effects hidden in it (none on clean data, at two
// noise levels), leave a residual within 1.3 x the noise, and recover the true modulus. The data
// are CalculiX solutions of the true problem (tests/identify_suite/generate_identify_suite.cpp,
// scripts/identify_suite.sh generate); each truth.json records the mesh check of the data.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "identify_suite_datasets.hpp"
#include "run_program.hpp"

namespace isospring {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

class IdentifySuite : public ::testing::TestWithParam<identify_suite::Dataset> {};

TEST_P(IdentifySuite, AddsExactlyTheHiddenEffects) {
  const identify_suite::Dataset& d = GetParam();
  const fs::path folder = fs::path(ISOSPRING_SOURCE_DIR) / "examples/identify_suite" / d.name;
  // The tissue-like datasets take ccx about 100 s of CPU each (about 460 s on the clamp-graded
  // reference, 400-600 s for large deformation): the ones not generated yet say so instead of
  // failing on missing files.
  if (d.poisson_ratio > 0.0 && !fs::exists(folder / "truth.json"))
    GTEST_SKIP() << folder << " is not generated yet: bash scripts/identify_suite.sh generate "
                 << d.name;
  ASSERT_TRUE(fs::exists(folder / "truth.json"))
      << folder << " is missing; regenerate with scripts/identify_suite.sh generate";
  json truth;
  std::ifstream(folder / "truth.json") >> truth;
  // The data must be converged well below the noise, or the test would not test identify: the
  // refined mesh's error (second order: the change between the meshes / 3) below a third of it.
  EXPECT_LT(truth["calculix"]["estimated_data_error_over_noise"].get<double>(), 1.0 / 3.0)
      << truth["calculix"].dump(1);

  testing::TemporaryFolder out;
  const auto start = std::chrono::steady_clock::now();
  const auto run = testing::run_isospring("identify " + (folder / "case.json").string() + " -o " +
                                          (out.path() / "r").string() + " --quiet");
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_EQ(run.exit_code, 0) << run.output;
  json report;
  std::ifstream(out.path() / "r" / "report.json") >> report;
  const std::set<std::string> hidden(truth["effects"].begin(), truth["effects"].end());
  const std::set<std::string> added(report["effects_added"].begin(), report["effects_added"].end());
  EXPECT_EQ(added, hidden) << "added " << report["effects_added"].dump() << ", hidden "
                           << truth["effects"].dump() << " (" << d.note << ")";
  const double noise = truth["noise_sigma"].get<double>();
  EXPECT_LT(report["rms_after"].get<double>(), 1.3 * noise);
  // E within 1 %: the data's mesh error and the noise are far below it; a graded or soft-layer
  // specimen's E is a different quantity (the mean or the bulk modulus), not compared.
  if (truth["hidden"]["modulus_gradient_per_length"] == 0.0 &&
      truth["hidden"]["soft_layer_modulus_factor"] == 0.0) {
    for (const auto& p : report["parameters"])
      if (p["name"] == "E") {
        EXPECT_NEAR(p["value"].get<double>(), truth["youngs_modulus"].get<double>(),
                    1e-2 * truth["youngs_modulus"].get<double>());
      }
  }
  RecordProperty("wall_seconds", std::to_string(seconds));
  std::printf("%s: added [%s], rms_after/noise %.2f, %.1f s\n", d.name.c_str(),
              report["effects_added"].dump().c_str(), report["rms_after"].get<double>() / noise,
              seconds);
}

INSTANTIATE_TEST_SUITE_P(Datasets, IdentifySuite, ::testing::ValuesIn(identify_suite::datasets()),
                         [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace isospring
