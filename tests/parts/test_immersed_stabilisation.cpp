// The stabilisation fallback on a real part: the CAx-IF nut turned obliquely (parts.json's
// caxif_nut_oblique) on a grid along the world's axes, whose stiffness at the default
// ghost_fraction (0.02) is not positive definite. The static solve, the calibration's reference
// and the identification all stabilise through analysis::assemble_stabilised_immersed, so each
// widens the ghost penalty to 0.04 with one warning and gives what those options give directly.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "isospring/analysis/immersed.hpp"
#include "isospring/fitting/identify_immersed.hpp"
#include "isospring/fitting/immersed_calibration.hpp"
#include "isospring/geometry/immersed_cad.hpp"
#include "parts_harness.hpp"

namespace isospring {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace parts_harness;

// The turned nut on the world's axes at the grid and problem of parts.json.
struct TurnedNut {
  geometry::ImmersedDomain domain;
  analysis::ImmersedOptions options;
};

bool have_turned_nut() {
  return fs::exists(kParts / "parts.json") && fs::exists(kParts / "caxif_nut.stp");
}

TurnedNut turned_nut() {
  const json part = find_part("caxif_nut_oblique");
  EXPECT_FALSE(part.is_null()) << "caxif_nut_oblique is not in parts.json";
  const json& grid = part.at("immersed");
  const geometry::CadSolid solid = read_placed_solid(part);
  return {geometry::immerse_solid(
              solid, immersion_options(part, grid, grid.at("degree").get<int>(), solid)),
          analysis_options(part, grid)};
}

double largest(const std::vector<Eigen::Vector3d>& values) {
  double out = 0.0;
  for (const auto& v : values) out = std::max(out, v.norm());
  return out;
}

// On the world's axes the turned nut's 1 mm grid leaves a basis function with a sliver of its
// support in the part next to cells whose share lies above the default ghost_fraction (0.02): the
// stiffness is then not positive definite (raising nitsche_factor to 16 or ghost_penalty to 0.1
// does not help). solve_immersed then penalises the cut cells below 0.04 and says so; the result
// is the one those options give directly. Without the ghost penalty it fails, naming the option.
TEST(ImmersedStabilisationFallback, TurnedNutOnTheWorldAxes) {
  if (!have_turned_nut()) GTEST_SKIP() << "tests/data/parts (third-party parts) is absent";
  const auto [domain, options] = turned_nut();

  const analysis::ImmersedResult widened = analysis::solve_immersed(domain, options);
  ASSERT_EQ(widened.warnings.size(), 1u);
  EXPECT_NE(widened.warnings[0].find("ghost_fraction 0.02"), std::string::npos)
      << widened.warnings[0];
  EXPECT_EQ(widened.ghost_fraction, 0.04);

  analysis::ImmersedOptions direct = options;
  direct.ghost_fraction = 0.04;
  const analysis::ImmersedResult same = analysis::solve_immersed(domain, direct);
  EXPECT_TRUE(same.warnings.empty());
  EXPECT_EQ(same.strain_energy, widened.strain_energy);
  EXPECT_EQ(same.ghost_faces, widened.ghost_faces);

  analysis::ImmersedOptions unstabilised = options;
  unstabilised.ghost_penalty = 0.0;
  try {
    analysis::solve_immersed(domain, unstabilised);
    ADD_FAILURE() << "an unstabilised turned nut factorised";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("raise ghost_fraction"), std::string::npos) << e.what();
  }
}

// The calibration factorises its reference's stiffness itself: at the default options it
// widens the penalty as the static solve does, says so in the calibration's warnings, and its
// reference is the static solve with ghost_fraction 0.04 (two Cholesky solves of one system).
TEST(ImmersedStabilisationFallback, CalibrationReferenceOfTheTurnedNut) {
  if (!have_turned_nut()) GTEST_SKIP() << "tests/data/parts (third-party parts) is absent";
  const auto [domain, options] = turned_nut();
  fitting::CalibrationSettings settings;
  settings.field_metrics = false;
  settings.gamma = 0.5;  // few stiffness groups: the fit is not what is tested here
  const fitting::ImmersedCalibrationResult calibrated =
      fitting::calibrate_immersed(domain, {{"weight", options}}, settings);
  const auto& warnings = calibrated.calibration.warnings;
  const auto widened = std::count_if(warnings.begin(), warnings.end(), [](const std::string& w) {
    return w.find("not positive definite with ghost_fraction 0.02") != std::string::npos;
  });
  EXPECT_EQ(widened, 1);
  ASSERT_EQ(calibrated.reference.size(), 1u);
  EXPECT_EQ(calibrated.reference[0].ghost_fraction, 0.04);

  analysis::ImmersedOptions direct = options;
  direct.ghost_fraction = 0.04;
  const analysis::ImmersedResult solved = analysis::solve_immersed(domain, direct);
  ASSERT_EQ(solved.control_displacements.size(),
            calibrated.reference[0].control_displacements.size());
  double worst = 0.0;
  for (size_t i = 0; i < solved.control_displacements.size(); ++i)
    worst = std::max(
        worst, (solved.control_displacements[i] - calibrated.reference[0].control_displacements[i])
                   .norm());
  EXPECT_LT(worst, 1e-9 * largest(solved.control_displacements));
}

// The identification assembles its own stiffness too: at the default options it widens the
// penalty, reports it in the result's warnings, and recovers a modulus 10 % above the nominal one
// from markers that the widened model's stiffer twin moved (noise-free, so to round-off).
TEST(ImmersedStabilisationFallback, IdentificationOfTheTurnedNut) {
  if (!have_turned_nut()) GTEST_SKIP() << "tests/data/parts (third-party parts) is absent";
  const auto [domain, options] = turned_nut();
  std::vector<fitting::Marker> markers;
  for (size_t b = 0; b < domain.boundary.size() && markers.size() < 40; b += 97) {
    if (domain.boundary[b].face == options.supports.front().face) continue;
    fitting::Marker m;
    m.load_case = "weight";
    m.position = domain.boundary[b].point;
    m.row = static_cast<int>(markers.size()) + 2;
    markers.push_back(m);
  }
  ASSERT_GE(markers.size(), 20u);
  analysis::ImmersedOptions stiffer = options;
  stiffer.material.youngs_modulus *= 1.1;
  stiffer.ghost_fraction = 0.04;
  const std::vector<Eigen::Vector3d> moved =
      fitting::simulate_immersed_markers(domain, {{"weight", stiffer}}, markers, {});
  for (size_t m = 0; m < markers.size(); ++m) markers[m].displacement = moved[m];

  fitting::IdentifyOptions identify;
  identify.holdout = false;
  identify.candidates = std::vector<std::string>{};
  identify.noise_sigma = 1e-6 * largest(moved);
  const fitting::IdentifyResult r =
      fitting::identify_immersed(domain, {{"weight", options}}, markers, identify);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("ghost_fraction 0.02"), std::string::npos) << r.warnings[0];
  ASSERT_FALSE(r.parameters.empty());
  EXPECT_NEAR(r.parameters[0].value, 1.1 * options.material.youngs_modulus,
              1e-6 * options.material.youngs_modulus);
}

}  // namespace
}  // namespace isospring
