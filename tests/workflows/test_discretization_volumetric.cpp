// identify's discretisation check on nearly incompressible materials: the rule that puts every
// level on B-bar from a given nu (off by default; reported in the check), and a generator of the
// DOFs the suite's cantilever needs for a third of 0.2 % noise at nu = 0.3 / 0.45 / 0.49 with and
// without it.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "isospring/fitting/discretization_check.hpp"
#include "isospring/io/case_file.hpp"
#include "isospring/io/case_refinement_ladder.hpp"
#include "isospring/io/markers.hpp"

namespace isospring {
namespace {

namespace fs = std::filesystem;

const fs::path kSuite = fs::path(ISOSPRING_SOURCE_DIR) / "examples/identify_suite";

// The suite's cantilever case (examples/identify_suite/cantilever_clean) at Poisson ratio nu.
io::Case cantilever(double nu, const std::vector<int>& elements = {10, 2, 2}) {
  nlohmann::json json;
  std::ifstream(kSuite / "cantilever_clean/case.json") >> json;
  json.erase("measurements");
  json["material"]["nu"] = nu;
  json["discretization"]["elements"] = elements;
  return io::build_case_from_json(json, kSuite / "cantilever_clean/case.json");
}

struct Placed {
  std::vector<fitting::Marker> markers;
  std::vector<fitting::MarkerPlacement> placements;
};

// The dataset's marker positions (their displacements do not enter the check).
Placed suite_markers(const io::Case& c) {
  io::MarkerFileOptions options;
  options.load_cases = {"tip_down", "tip_side", "pull"};
  Placed p;
  p.markers = io::read_markers_csv(kSuite / "cantilever_clean/markers.csv", options).markers;
  p.placements = fitting::place_markers(c.problem.patches, p.markers, 1e-6).placements;
  return p;
}

fitting::DiscretizationCheck check(const io::Case& c, const Placed& p, double nu, double noise,
                                   fitting::DiscretizationOptions options) {
  options.ladder = io::case_refinement_ladder(c);
  options.intermediate = io::case_refinement_intermediate(c);
  return fitting::check_discretization(c.problem, p.markers, p.placements, 1e7, nu, noise, options);
}

// nu >= 0.48: every level on B-bar, the chosen problem too (even the case's own level, which then
// differs from the input problem); below: the displacement formulation; the threshold is an
// option. A large noise makes the case's own level good enough after one finer level.
TEST(DiscretizationVolumetric, BbarFromPoissonRatio0p48) {
  fitting::DiscretizationOptions options;
  EXPECT_GT(options.bbar_from_poisson, 0.5);  // off by default (discretization_check.hpp)
  options.bbar_from_poisson = 0.48;
  options.max_levels = 1;
  for (double nu : {0.45, 0.49}) {
    const io::Case c = cantilever(nu, {4, 1, 1});
    const Placed p = suite_markers(c);
    const fitting::DiscretizationCheck result = check(c, p, nu, 1.0, options);
    ASSERT_TRUE(result.done);
    EXPECT_EQ(result.chosen, 0);
    if (nu < 0.48) {
      EXPECT_EQ(result.volumetric, "displacement") << result.volumetric_rule;
      EXPECT_FALSE(result.chosen_problem.has_value());
    } else {
      EXPECT_EQ(result.volumetric, "bbar") << result.volumetric_rule;
      ASSERT_TRUE(result.chosen_problem.has_value());
      EXPECT_EQ(result.chosen_problem->volumetric, analysis::Volumetric::kBbar);
      EXPECT_NE(result.volumetric_rule.find("0.49 >= 0.48"), std::string::npos)
          << result.volumetric_rule;
    }
  }
  options.bbar_from_poisson = 0.6;
  const io::Case c = cantilever(0.49, {4, 1, 1});
  const fitting::DiscretizationCheck off = check(c, suite_markers(c), 0.49, 1.0, options);
  EXPECT_EQ(off.volumetric, "displacement") << off.volumetric_rule;
}

// Generator of the locking table of examples/identify_suite/README.md (run with
// --gtest_also_run_disabled_tests): for nu = 0.3 / 0.45 / 0.49, the level the check chooses on
// the suite's cantilever (ladder degree 2 -> 3, then doubling; intermediate levels) for a third
// of the noise 0.2 % x the largest displacement (the dataset's noise_sigma), with the
// displacement formulation and with B-bar on every level.
TEST(DiscretizationVolumetric, DISABLED_CantileverDofsTable) {
  for (const auto& [nu, dataset] :
       {std::pair{0.3, "cantilever_clean"}, std::pair{0.45, "cantilever_clean_nu045"},
        std::pair{0.49, "cantilever_clean_nu049"}}) {
    // The dataset's noise; before its data exist, the nu = 0.3 dataset's (its largest
    // displacement, the tip's bending deflection, changes by a few % with nu).
    nlohmann::json truth;
    std::ifstream in(kSuite / dataset / "truth.json");
    if (!in) {
      std::printf("nu %.2f: %s/truth.json missing, the nu = 0.3 dataset's noise used\n", nu,
                  dataset);
      in = std::ifstream(kSuite / "cantilever_clean/truth.json");
    }
    in >> truth;
    const double noise = truth["noise_sigma"].get<double>();
    const io::Case c = cantilever(nu);
    const Placed p = suite_markers(c);
    for (double from : {1.0, 0.0}) {  // never B-bar, always B-bar
      fitting::DiscretizationOptions options;
      options.bbar_from_poisson = from;
      const auto start = std::chrono::steady_clock::now();
      const fitting::DiscretizationCheck r = check(c, p, nu, noise, options);
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      const auto& used = r.levels[static_cast<size_t>(r.chosen)];
      std::printf("nu %.2f %-12s: %s, %d DOFs, error/noise %.3f%s (check %.0f s, noise %.3g m)\n",
                  nu, r.volumetric.c_str(), used.description.c_str(), used.dofs,
                  used.error_rms / noise, r.within_target ? "" : " NOT within target", seconds,
                  noise);
      for (const auto& level : r.levels)
        std::printf("    level %d %s: %d DOFs, error/noise %.3f, %.1f s\n", level.level,
                    level.description.c_str(), level.dofs, level.error_rms / noise, level.seconds);
      std::fflush(stdout);
    }
  }
}

}  // namespace
}  // namespace isospring
