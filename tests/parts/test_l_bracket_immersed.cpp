// The CAx-IF L-bracket (../shared/cad/l_bracket_caxif.stp) analysed immersed, with the supports and
// loads of examples/l_bracket/case.json (the long leg's end y = 60 mm clamped: face 3; a uniform
// traction of 1 MPa on the short leg's end x = 50 mm: face 7, along -y and along +z), against
// (1) CalculiX at h = 2 mm (examples/l_bracket/calculix_reference.json, gmsh + C3D10) and (2) the
// body-fitted 57-patch analysis of the same file (`isospring analyze examples/l_bracket/case.json`
// run here). Every displacement component above 10 % of the largest at the loaded end's four
// corners must agree to 0.5 % with both. Skipped without ../shared.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "isospring/analysis/immersed.hpp"
#include "isospring/geometry/immersed_cad.hpp"
#include "run_program.hpp"

namespace isospring {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const fs::path kExample = fs::path(ISOSPRING_SOURCE_DIR) / "examples/l_bracket";
const fs::path kPart = fs::path(ISOSPRING_SHARED_DIR) / "cad/l_bracket_caxif.stp";
constexpr int kClampFace = 3;   // y = 60 mm (`isospring info` numbering)
constexpr int kLoadedFace = 7;  // x = 50 mm

// The body-fitted displacement of the control point at `at` (a patch corner, which box patches
// interpolate), from analyze's CSV (i,x,y,z,ux,uy,uz).
Eigen::Vector3d body_fitted_at(const fs::path& csv, const Eigen::Vector3d& at) {
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  double best = 1e300;
  Eigen::Vector3d u = Eigen::Vector3d::Zero();
  while (std::getline(in, line)) {
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream fields(line);
    double i, x, y, z, ux, uy, uz;
    fields >> i >> x >> y >> z >> ux >> uy >> uz;
    const double d = (Eigen::Vector3d(x, y, z) - at).norm();
    if (d < best) {
      best = d;
      u = Eigen::Vector3d(ux, uy, uz);
    }
  }
  EXPECT_LT(best, 1e-9) << "no control point at the corner";
  return u;
}

TEST(LBracketImmersed, LoadedEndAgreesWithCalculixAndTheBodyFittedModel) {
  if (!fs::exists(kPart))
    GTEST_SKIP() << "../shared/cad/l_bracket_caxif.stp (third-party CAD part) is not present";
  // Cells of 2.5 mm: every plane face of the L lies on a grid plane, so only the holes cut cells.
  geometry::ImmersionOptions immersion;
  immersion.degree = 3;
  immersion.cells = Eigen::Vector3i(20, 24, 40);
  immersion.tolerance = 1e-6;
  immersion.max_depth = 2;
  const geometry::ImmersedDomain domain =
      geometry::immerse_solid(geometry::read_cad_solid(kPart), immersion);

  const testing::TemporaryFolder out;
  const auto run = testing::run_isospring("analyze " + (kExample / "case.json").string() + " -o " +
                                          out.path().string() + " --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  std::ifstream file(kExample / "calculix_reference.json");
  const json reference = json::parse(file);
  const json* finest = nullptr;
  for (const auto& r : reference["runs"])
    if (finest == nullptr || r["h_mm"].get<double>() < (*finest)["h_mm"].get<double>()) finest = &r;
  ASSERT_NE(finest, nullptr);

  int compared = 0;
  for (const std::string load_case : {"shear_y", "shear_z"}) {
    analysis::ImmersedOptions options;
    options.material.youngs_modulus = 210e9;
    options.material.poisson_ratio = 0.3;
    analysis::ImmersedSupport clamp;
    clamp.face = kClampFace;
    clamp.fixed = {true, true, true};
    options.supports = {clamp};
    analysis::ImmersedTraction traction;
    traction.face = kLoadedFace;
    traction.value =
        load_case == "shear_y" ? Eigen::Vector3d(0, -1e6, 0) : Eigen::Vector3d(0, 0, 1e6);
    options.tractions = {traction};
    const analysis::ImmersedResult result = analysis::solve_immersed(domain, options);

    const json& corners = (*finest)["load_cases"][load_case]["corners"];
    double largest = 0.0;
    for (const auto& c : corners)
      for (int k = 0; k < 3; ++k)
        largest = std::max(largest, std::abs(c["u_m"][static_cast<size_t>(k)].get<double>()));
    for (const auto& c : corners) {
      const auto a = c["at_m"].get<std::array<double, 3>>();
      const Eigen::Vector3d at(a[0], a[1], a[2]);
      const Eigen::Vector3d ours = analysis::evaluate_immersed(domain, result, at).displacement;
      const Eigen::Vector3d fitted =
          body_fitted_at(out.path() / (load_case + "_control_displacements.csv"), at);
      for (int k = 0; k < 3; ++k) {
        const double calculix = c["u_m"][static_cast<size_t>(k)].get<double>();
        if (std::abs(calculix) < 0.1 * largest) continue;
        ++compared;
        std::printf(
            "%s (%g, %g, %g) u%c: immersed %.6e (%d DOFs), body-fitted %.6e, CalculiX "
            "%.6e: %+.3f %%, %+.3f %%\n",
            load_case.c_str(), at.x(), at.y(), at.z(), "xyz"[k], ours[k], result.dofs, fitted[k],
            calculix, 100 * (ours[k] / fitted[k] - 1), 100 * (ours[k] / calculix - 1));
        EXPECT_NEAR(ours[k] / calculix, 1.0, 5e-3) << load_case << " u"
                                                   << "xyz"[k];
        EXPECT_NEAR(ours[k] / fitted[k], 1.0, 5e-3) << load_case << " u"
                                                    << "xyz"[k];
      }
    }
  }
  EXPECT_EQ(compared, 20);  // shear_y: ux and uy at 4 corners; shear_z: all 3 at 4 corners
}

}  // namespace
}  // namespace isospring
