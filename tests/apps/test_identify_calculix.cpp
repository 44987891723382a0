// The measured-data loop on data from an independent code: CalculiX (C3D20R hexahedra) computes
// a clamped bar under two load cases WITH self-weight; the identification starts from the
// nominal isogeometric model WITHOUT it and must add gravity with g close to 9.81 m/s^2 along -y.
// Skipped when ccx is not on PATH.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>

#include "isospring/fitting/identify.hpp"
#include "isospring/fitting/measure.hpp"
#include "isospring/io/calculix.hpp"
#include "isospring/nurbs/refine.hpp"

namespace isospring {
namespace {

namespace fs = std::filesystem;

constexpr double kLength = 0.2, kSection = 0.02, kGravity = 9.81;

// Clamped at x = 0; L1 tension and L2 transverse shear (z) on x = L. Soft (E = 1 GPa) so that
// self-weight bends the bar by ~0.5 mm, against ~0.8 mm from the L2 tip load.
analysis::Problem bar(bool with_gravity) {
  const nurbs::KnotVector linear(1, {0, 0, 1, 1});
  std::vector<Eigen::Vector3d> points;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) points.emplace_back(kLength * i, kSection * j, kSection * k);
  analysis::Problem problem;
  problem.formulation = analysis::Formulation::kSolid;
  problem.material = {1e9, 0.3, 7800, 1.0};
  problem.patches.push_back(
      nurbs::k_refine(nurbs::Patch({linear, linear, linear}, points), {2, 2, 2}, {16, 3, 3}));
  analysis::Support clamp;
  clamp.side = {0, 0, 0};
  clamp.fixed = {true, true, true};
  problem.supports.push_back(clamp);
  analysis::LoadCase tension, shear;
  tension.id = "L1";
  tension.tractions.push_back({{0, 0, 1}, Eigen::Vector3d(2e5, 0, 0), {}});
  shear.id = "L2";
  shear.tractions.push_back({{0, 0, 1}, Eigen::Vector3d(0, 0, 1e4), {}});
  if (with_gravity) tension.gravity = shear.gravity = Eigen::Vector3d(0, -kGravity, 0);
  problem.load_cases = {tension, shear};
  return problem;
}

TEST(IdentifyCalculix, FindsTheSelfWeightInCalculixData) {
  if (std::system("command -v ccx > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "ccx (CalculiX, Debian package calculix-ccx) is not on PATH";
  std::random_device device;
  const fs::path dir =
      fs::temp_directory_path() / ("isospring-identify-ccx-" + std::to_string(device()));
  fs::create_directories(dir);
  const io::CalculixDeck deck = io::make_calculix_deck(bar(true));
  std::ofstream(dir / "deck.inp") << deck.text;
  const std::string command = "cd '" + dir.string() + "' && ccx -i deck > ccx.log 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << "ccx failed; see " << dir / "ccx.log";
  const auto blocks = io::read_calculix_dat(dir / "deck.dat");
  ASSERT_EQ(blocks.size(), 2u);

  // Markers: every third ccx node off the clamped end, both load cases.
  std::vector<fitting::Marker> markers;
  for (size_t s = 0; s < blocks.size(); ++s)
    for (size_t n = 0; n < deck.nodes.size(); n += 3) {
      if (deck.nodes[n].x() < 1e-9) continue;
      fitting::Marker m;
      m.load_case = deck.load_case_ids[s];
      m.position = deck.nodes[n];
      m.displacement = blocks[s].nodes.at(static_cast<int>(n) + 1);
      m.row = static_cast<int>(markers.size()) + 2;
      markers.push_back(m);
    }
  ASSERT_GT(markers.size(), 200u);
  const analysis::Problem nominal = bar(false);
  const fitting::PlacementResult placed = fitting::place_markers(nominal.patches, markers, 1e-9);
  ASSERT_TRUE(placed.outside.empty());
  // The linear candidates only: this test is about data from an independent code. The bar
  // bends by ~1 mm over 200 mm (strains ~1e-4), where large-deformation effects are far below
  // the data's resolution, and geometric_nonlinearity's Newton solves on these 1,350 DOFs would
  // multiply the test's time; that candidate is tested in test_identify_nonlinear.cpp (found at
  // 14 % deflection, not added at 0.014 %) and the whole library in 3D by Identify3D.
  fitting::IdentifyOptions options;
  // The data carry no noise, so no discretisation meets a target relative to it, and the first
  // refined level (32 x 6 x 6, 6,528 DOFs) would make the test slow: the check is off (a budget
  // below the first refinement is an input error, since there would be no estimate at all).
  options.discretization.enabled = false;
  options.candidates = {"gravity", "support_compliance", "stiffness_gradient", "rigid_offset",
                        "load_scale"};
  const fitting::IdentifyResult r = fitting::identify(nominal, markers, placed.placements, options);
  fs::remove_all(dir);

  const auto& added = r.effects_added;
  ASSERT_NE(std::find(added.begin(), added.end(), "gravity"), added.end())
      << "effects added: " << added.size();
  for (const fitting::ParameterEstimate& p : r.parameters) {
    // Different discretisations (C3D20R vs quadratic NURBS, same 16 x 3 x 3 grid) differ by
    // ~0.1 % in the deflections; 1 % on g leaves room for that.
    if (p.name == "gy") {
      EXPECT_NEAR(p.value, -kGravity, 0.01 * kGravity);
    }
    if (p.name == "gx" || p.name == "gz") {
      EXPECT_LT(std::abs(p.value), 0.01 * kGravity);
    }
  }
  // The prior E is the truth; the fit must not move it to mimic the missing load.
  EXPECT_NEAR(r.youngs_modulus / 1e9, 1.0, 0.01);
  EXPECT_LT(r.after.rms, 0.05 * r.before.rms);
  EXPECT_FALSE(r.discretization.done);
}

}  // namespace
}  // namespace isospring
