// The 6-patch plate with a central hole: exact area, right-handed patches, points on the exact
// hole circle, conforming interfaces (every shared side's control points coincide).
#include <gtest/gtest.h>

#include <cmath>

#include "isospring/geometry/construction.hpp"
#include "isospring/geometry/measure.hpp"
#include "isospring/geometry/plate_with_central_hole.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::geometry {
namespace {

TEST(PlateWithCentralHole, AreaIsPlateMinusHole) {
  const double length = 0.08, width = 0.02, radius = 0.004;
  const Patches patches = plate_with_central_hole(length, width, radius);
  ASSERT_EQ(patches.size(), 6u);
  // Exact geometry, Gauss quadrature: agreement to round-off (see test_primitives.cpp).
  EXPECT_NEAR(measure(patches) / (length * width - M_PI * radius * radius), 1.0, 1e-12);
  for (size_t p = 0; p < patches.size(); ++p)
    EXPECT_GT(jacobian_range(patches[p], 6).min, 0.0) << "patch " << p;
}

TEST(PlateWithCentralHole, HoleSidesLieOnTheCircle) {
  const double radius = 0.004;
  const Patches patches = plate_with_central_hole(0.08, 0.02, radius);
  const Eigen::Vector3d centre(0.04, 0.01, 0.0);
  for (int p = 1; p <= 4; ++p)
    for (int i = 0; i <= 20; ++i) {
      const Eigen::Vector3d x = patches[static_cast<size_t>(p)].point({i / 20.0, 0.0, 0.0});
      EXPECT_NEAR((x - centre).norm(), radius, 1e-15) << "patch " << p << " u " << i / 20.0;
    }
}

TEST(PlateWithCentralHole, InterfacesConform) {
  const Patches patches = plate_with_central_hole(0.08, 0.02, 0.004);
  // Every control point on a patch boundary that is not on the plate's outer boundary or the
  // hole must coincide with a control point of another patch (what the DofMap glues). Count the
  // points matched in another patch: on the 4 diagonals, 2 points (hole, square corner) in each
  // of the 2 ring patches meeting there; on the 2 square sides shared with a rectangle, the
  // rectangle's 3 points and the ring patch's side midpoint (its corners are counted already).
  int matched = 0;
  for (size_t p = 0; p < patches.size(); ++p)
    for (const Eigen::Vector3d& x : patches[p].control_points()) {
      bool found = false;
      for (size_t q = 0; q < patches.size() && !found; ++q)
        if (q != p)
          for (const Eigen::Vector3d& y : patches[q].control_points())
            if ((x - y).norm() < 1e-14) found = true;
      matched += found;
    }
  EXPECT_EQ(matched, 4 * 2 * 2 + 2 * (3 + 1));
  // The square sides also agree as curves, not only at control points (same weights).
  for (int i = 0; i <= 10; ++i) {
    const double t = i / 10.0;
    EXPECT_LT((patches[0].point({t, 0.0, 0.0}) - patches[1].point({t, 1.0, 0.0})).norm(), 1e-15);
    EXPECT_LT((patches[5].point({t, 0.0, 0.0}) - patches[3].point({t, 1.0, 0.0})).norm(), 1e-15);
  }
  // The loaded ends.
  EXPECT_NEAR(patches[0].point({0.3, 1.0, 0.0}).x(), 0.0, 1e-15);
  EXPECT_NEAR(patches[5].point({0.3, 1.0, 0.0}).x(), 0.08, 1e-15);
}

TEST(PlateWithCentralHole, SquarePlateHasFourPatches) {
  const Patches patches = plate_with_central_hole(0.02, 0.02, 0.004);
  ASSERT_EQ(patches.size(), 4u);
  EXPECT_NEAR(measure(patches) / (0.02 * 0.02 - M_PI * 0.004 * 0.004), 1.0, 1e-12);
}

TEST(PlateWithCentralHole, RejectsBadParameters) {
  EXPECT_THROW(plate_with_central_hole(0.08, 0.02, 0.01), nurbs::InputError);
  EXPECT_THROW(plate_with_central_hole(0.01, 0.02, 0.004), nurbs::InputError);
  EXPECT_THROW(plate_with_central_hole(0.08, -0.02, 0.004), nurbs::InputError);
}

}  // namespace
}  // namespace isospring::geometry
