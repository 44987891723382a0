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
