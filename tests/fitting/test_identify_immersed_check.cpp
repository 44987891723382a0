// The discretisation check on an immersed model (identify_immersed_check.hpp): its decisions on
// CadQuery's cylinder (r 5 mm, h 10 mm) clamped on one end disk and pulled on the other, against
// the immersed solver on a finer grid that the check never sees (analysis::solve_immersed on
// 8 x 8 x 8 cells, evaluated at the markers): a level whose true error is above the target is
// refused, the level chosen is within it; the DOF budget's two outcomes (a finest level used with
// its error carried into the loop, no level at all) are clear.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <string>

#include "isospring/fitting/identify_immersed.hpp"
#include "isospring/fitting/identify_immersed_check.hpp"
#include "isospring/geometry/immersed_cad.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::fitting {
namespace {

const std::string kPart =
    std::string(ISOSPRING_SOURCE_DIR) + "/examples/immersed/cube_cylinder.step";

const geometry::CadSolid& cylinder_solid() {
  static const geometry::CadSolid solid = geometry::read_cad_solid(kPart, 0);
  return solid;
}

// Each grid immersed once for all tests (the cut cells' quadrature is most of their CPU).
const geometry::ImmersedDomain& immersed(int cells) {
  static std::map<int, geometry::ImmersedDomain> domains;
  auto it = domains.find(cells);
  if (it == domains.end()) {
    geometry::ImmersionOptions o;
    o.degree = 2;
    o.cells = Eigen::Vector3i::Constant(cells);
    it = domains.emplace(cells, geometry::immerse_solid(cylinder_solid(), o)).first;
  }
  return it->second;
}

// Level 0 (2 cells per direction) and the ladder 3, 4, 6 cells: steps of about sqrt 2, as
// `isospring identify`'s ladder (workflows/immersed_grid_ladder.hpp).
constexpr int kCells[] = {2, 3, 4, 6};

ImmersedLadder ladder() {
  ImmersedLadder l;
  l.level = [](int level) -> std::optional<ImmersedLevel> {
    if (level >= static_cast<int>(std::size(kCells))) return std::nullopt;
    const int n = kCells[level];
    return ImmersedLevel{immersed(n), std::to_string(n) + " cells per direction", 0.0};
  };
  return l;
}

struct Case {
  geometry::ImmersedDomain domain = immersed(kCells[0]);
  std::vector<ImmersedCalibrationCase> cases;
  std::vector<Marker> markers;
};

// Clamped on its end disk (face 0), 500 Pa along the axis on the other (face 1); markers at
// every 5th boundary quadrature point off the clamp.
Case cylinder() {
  Case c;
  ImmersedCalibrationCase lc;
  lc.id = "axial";
  lc.options.material.youngs_modulus = 1e6;
  lc.options.material.poisson_ratio = 0.3;
  lc.options.material.density = 1100.0;
  lc.options.supports = {{0, {true, true, true}, Eigen::Vector3d::Zero(), nullptr, false}};
  lc.options.tractions = {{1, Eigen::Vector3d(200, 0, 500), nullptr}};
  c.cases.push_back(lc);
  int k = 0;
  for (const auto& b : c.domain.boundary) {
    if (b.face == 0 || k++ % 5 != 0) continue;
    Marker m;
    m.load_case = lc.id;
    m.position = b.point;
    m.row = static_cast<int>(c.markers.size()) + 2;
    c.markers.push_back(m);
  }
  return c;
}

// The solution at the markers on `cells` per direction (the solver itself, not the loop).
std::vector<Eigen::Vector3d> solved_at_markers(const Case& c, int cells) {
  const geometry::ImmersedDomain& domain = immersed(cells);
  const analysis::ImmersedResult solved = analysis::solve_immersed(domain, c.cases[0].options);
  std::vector<Eigen::Vector3d> u;
  for (const Marker& m : c.markers)
    u.push_back(analysis::evaluate_immersed(domain, solved, m.position).displacement);
  return u;
}

double rms_difference(const std::vector<Eigen::Vector3d>& a,
                      const std::vector<Eigen::Vector3d>& b) {
  double sum = 0.0;
  for (size_t m = 0; m < a.size(); ++m) sum += (a[m] - b[m]).squaredNorm();
  return std::sqrt(sum / (3.0 * static_cast<double>(a.size())));
}

// The reference of the decisions: 8 cells per direction, finer than every level of the ladder.
const std::vector<Eigen::Vector3d>& reference() {
  static const std::vector<Eigen::Vector3d> u = solved_at_markers(cylinder(), 8);
  return u;
}

TEST(ImmersedDiscretizationCheck, RefusesACoarseGridAndAcceptsOneWithinTheTarget) {
  const Case c = cylinder();
  ASSERT_GE(c.markers.size(), 20u);
  // The true error at the markers of the grid of 2 cells, against 8.
  const double error_coarse = rms_difference(solved_at_markers(c, kCells[0]), reference());
  // A noise level whose target (a third of it) is half the coarse grid's true error: the check
  // must refuse level 0 and choose a level whose true error is within the target.
  const double noise = 1.5 * error_coarse;
  DiscretizationOptions options;
  const DiscretizationCheck check =
      check_immersed_discretization(c.domain, c.cases, c.markers, 1.0, noise, options, ladder());
  ASSERT_TRUE(check.done) << check.note;
  EXPECT_TRUE(check.within_target) << check.note;
  ASSERT_GE(check.chosen, 1) << "level 0 accepted with a true error twice the target";
  const int cells = kCells[check.levels[static_cast<size_t>(check.chosen)].level];
  const double error_chosen = rms_difference(solved_at_markers(c, cells), reference());
  EXPECT_LE(error_chosen, check.target) << cells << " cells chosen";
  // The estimates bound the true errors from above (their triangle inequality), and not by
  // orders of magnitude: level 0's within a factor 3 of its truth.
  EXPECT_GE(check.levels[0].error_rms, error_coarse * 0.9);
  EXPECT_LE(check.levels[0].error_rms, error_coarse * 3.0);
  EXPECT_EQ(
      check.levels[0].dofs, 3 * [&] {
        int nodes = 0;
        for (bool a : analysis::solve_immersed(c.domain, c.cases[0].options).active) nodes += a;
        return nodes;
      }());
  std::printf(
      "immersed check: 2 cells true error %.3e m (estimate %.3e), target %.3e; chose %d cells, "
      "true error %.3e m\n",
      error_coarse, check.levels[0].error_rms, check.target, cells, error_chosen);
  // The estimate per marker is the chosen level's.
  EXPECT_EQ(check.marker_error.size(), c.markers.size());
}

TEST(ImmersedDiscretizationCheck, AcceptsTheCaseGridWhenTheNoiseIsLarge) {
  // With the noise 100 x the coarse grid's true error, level 0 is chosen on two finer levels.
  const Case c = cylinder();
  const double noise = 100.0 * rms_difference(solved_at_markers(c, kCells[0]), reference());
  const DiscretizationCheck check = check_immersed_discretization(
      c.domain, c.cases, c.markers, 1.0, noise, DiscretizationOptions(), ladder());
  EXPECT_TRUE(check.within_target);
  EXPECT_EQ(check.chosen, 0);
}

TEST(ImmersedDiscretizationCheck, TheBudgetStopsTheLadderWithAClearNote) {
  const Case c = cylinder();
  const double noise = 1e-3 * rms_difference(solved_at_markers(c, kCells[0]), reference());
  DiscretizationOptions options;
  const DiscretizationCheck full =
      check_immersed_discretization(c.domain, c.cases, c.markers, 1.0, noise, options, ladder());
  ASSERT_GE(full.levels.size(), 3u);
  // A budget that admits levels 0 and 1 only.
  options.max_dofs = full.levels[1].dofs;
  const DiscretizationCheck check =
      check_immersed_discretization(c.domain, c.cases, c.markers, 1.0, noise, options, ladder());
  EXPECT_FALSE(check.within_target);
  EXPECT_TRUE(check.budget_exhausted);
  EXPECT_EQ(check.chosen, 1);
  EXPECT_NE(check.note.find("DOF budget"), std::string::npos) << check.note;
  EXPECT_NE(check.note.find("--max-dofs"), std::string::npos) << check.note;
  EXPECT_EQ(check.marker_error.size(), c.markers.size());
  // No finer level within the budget at all: an error naming the option and the fix.
  options.max_dofs = full.levels[0].dofs;
  try {
    check_immersed_discretization(c.domain, c.cases, c.markers, 1.0, noise, options, ladder());
    FAIL() << "no error";
  } catch (const nurbs::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("max_dofs"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace isospring::fitting
