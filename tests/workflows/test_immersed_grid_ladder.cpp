// The ladder of background grids of identify's immersed discretisation check
// (immersed_grid_ladder.hpp): the levels' grids, and the bound on a level's active DOFs that
// decides, before its immersion, whether it fits the budget: it must never be below the count of
// the immersed level (a level within the budget would be skipped otherwise), and it should not
// be far above it.
#include "isospring/workflows/immersed_grid_ladder.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "isospring/analysis/immersed.hpp"

namespace isospring::workflows {
namespace {

const std::string kPart =
    std::string(ISOSPRING_SOURCE_DIR) + "/examples/immersed/cube_cylinder.step";

long active_dofs(const geometry::ImmersedDomain& domain) {
  // The assembly's count: control points that carry DOFs, times 3.
  analysis::ImmersedOptions o;
  o.material.youngs_modulus = 1e6;
  o.material.poisson_ratio = 0.3;
  o.supports = {{0, {true, true, true}, Eigen::Vector3d::Zero(), nullptr, false}};
  return static_cast<long>(analysis::assemble_immersed(domain, o).force.size());
}

TEST(ImmersedGridLadder, LevelsShrinkTheCellsBySqrtTwoAtTheCaseDegree) {
  const geometry::CadSolid solid = geometry::read_cad_solid(kPart, 0);
  geometry::ImmersionOptions base;
  base.degree = 2;
  base.cells = Eigen::Vector3i(4, 3, 2);
  const geometry::ImmersedDomain level0 = geometry::immerse_solid(solid, base);
  std::string description;
  const auto one = immersed_ladder_grid(base, level0, 1, &description);
  ASSERT_TRUE(one);
  EXPECT_EQ(one->cells, Eigen::Vector3i(6, 4, 3));  // round(4 sqrt 2), round(3 sqrt 2), 2 + 1
  EXPECT_EQ(one->degree, 2);
  EXPECT_EQ(description, "degree 2, 6 x 4 x 3 cells");
  const auto two = immersed_ladder_grid(base, level0, 2, &description);
  ASSERT_TRUE(two);
  EXPECT_EQ(two->cells, Eigen::Vector3i(8, 6, 4));  // halved every two levels
  EXPECT_FALSE(immersed_ladder_grid(base, level0, 0, &description));
}

TEST(ImmersedGridLadder, TheDofBoundIsNeverBelowTheImmersedCount) {
  const geometry::CadSolid solid = geometry::read_cad_solid(kPart, 0);
  geometry::ImmersionOptions base;
  base.degree = 2;
  base.cells = Eigen::Vector3i::Constant(3);
  const geometry::ImmersedDomain level0 = geometry::immerse_solid(solid, base);
  for (int level = 1; level <= 2; ++level) {
    const std::optional<long> bound = immersed_ladder_dofs_bound(base, level0, level);
    ASSERT_TRUE(bound);
    const auto grid = immersed_ladder_grid(base, level0, level, nullptr);
    const long count = active_dofs(geometry::immerse_solid(solid, *grid));
    EXPECT_GE(*bound, count) << "level " << level;
    EXPECT_LE(*bound, 2 * count) << "level " << level;
    std::printf("level %d (%d cells): %ld active DOFs, bound %ld\n", level, grid->cells[0], count,
                *bound);
  }
  // Graded grids have no bound (their cells are not those of level 0 refined).
  base.grading = {{0, 0.0, 1e-3, 1.5}};
  EXPECT_FALSE(immersed_ladder_dofs_bound(base, level0, 1));
}

}  // namespace
}  // namespace isospring::workflows
