#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "isospring/nurbs/point_inversion.hpp"
#include "random_patch.hpp"

using namespace isospring::nurbs;

TEST(PointInversion, RecoversParametersOfPointsOnThePatch) {
  std::mt19937 rng(9);
  int recovered = 0, total = 0;
  for (int dim = 1; dim <= 3; ++dim)
    for (int trial = 0; trial < 5; ++trial) {
      // Mildly distorted patches (a perturbed regular grid) so the map is invertible.
      Patch base = isospring::testing::random_patch(rng, dim, 3, trial % 2 == 1, 2);
      std::vector<Eigen::Vector3d> points = base.control_points();
      std::uniform_real_distribution<double> noise(-0.05, 0.05);
      for (int i = 0; i < base.num_points(); ++i) {
        const auto ijk = base.net_position(i);
        points[static_cast<size_t>(i)] = Eigen::Vector3d(ijk[0], ijk[1], ijk[2]) +
                                         Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
      }
      const Patch patch(base.all_knots(), points, base.weights());
      for (int q = 0; q < 20; ++q) {
        const Param u = isospring::testing::random_param(rng, patch);
        const Eigen::Vector3d x = patch.point(u);
        const Inversion inv = invert_point(patch, x);
        ++total;
        EXPECT_TRUE(inv.converged);
        EXPECT_LT(inv.distance, 1e-10);
        if ((patch.point(inv.param) - x).norm() < 1e-10) ++recovered;
      }
    }
  EXPECT_EQ(recovered, total);
}

TEST(PointInversion, ClosestPointOnACircularArc) {
  const double w = std::sqrt(0.5);
  const Patch arc({KnotVector(2, {0, 0, 0, 1, 1, 1})}, {{2, 0, 0}, {2, 2, 0}, {0, 2, 0}},
                  {1, w, 1});
  // A point outside the arc at angle 30 degrees: the closest point is radial, distance r - 2.
  const double angle = M_PI / 6;
  const Eigen::Vector3d x(3 * std::cos(angle), 3 * std::sin(angle), 0.5);
  const Inversion inv = invert_point(arc, x);
  EXPECT_TRUE(inv.converged);
  EXPECT_NEAR(inv.distance, std::sqrt(1.0 + 0.25), 1e-12);
  EXPECT_NEAR(std::atan2(inv.point.y(), inv.point.x()), angle, 1e-12);
  // Beyond the end of the arc the closest point is the end point (a bound is active).
  const Inversion end = invert_point(arc, Eigen::Vector3d(3, -1, 0));
  EXPECT_NEAR(end.param[0], 0.0, 1e-14);
  EXPECT_NEAR((end.point - Eigen::Vector3d(2, 0, 0)).norm(), 0.0, 1e-14);
}

TEST(PointInversion, StartWithinRoundOffOfABoundIsPinned) {
  // A start a rounding error inside v = 1 must still move along u (seen from the point locator).
  const double w = std::sqrt(0.5);
  const Patch annulus({KnotVector(2, {0, 0, 0, 1, 1, 1}), KnotVector(1, {0, 0, 1, 1})},
                      {{1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}},
                      {1, w, 1, 1, w, 1});
  const Eigen::Vector3d x(3 * std::cos(0.3), 3 * std::sin(0.3), 0);  // outside the outer arc
  const Inversion inv = invert_point(annulus, x, Param{0.9, 1.0 - 1e-16, 0});
  EXPECT_TRUE(inv.converged);
  EXPECT_NEAR(inv.distance, 1.0, 1e-13);
  EXPECT_NEAR(std::atan2(inv.point.y(), inv.point.x()), 0.3, 1e-13);
}

TEST(PointInversion, ClosestPointIsAccurateToRoundOffNotSqrtEpsilon) {
  // Off-surface point above a curved surface: the foot of the perpendicular on a sphere-like
  // patch is radial. Comparing squared distances alone stops at ~1e-9 relative; the cosine
  // criterion reaches ~1e-14.
  const double w = std::sqrt(0.5);
  const Patch arc({KnotVector(2, {0, 0, 0, 1, 1, 1})}, {{5, 0, 0}, {5, 5, 0}, {0, 5, 0}},
                  {1, w, 1});
  for (double angle : {0.1, 0.7, 1.3}) {
    const Eigen::Vector3d x(6 * std::cos(angle), 6 * std::sin(angle), 0);
    const Inversion inv = invert_point(arc, x, Param{0.5, 0, 0});
    EXPECT_NEAR(std::atan2(inv.point.y(), inv.point.x()), angle, 1e-13);
  }
}
