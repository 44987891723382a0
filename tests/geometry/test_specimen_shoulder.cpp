// The specimen shoulder (straight run + circular fillets) added to the plate with a central hole:
// exact area against the closed form, fillet sides on the exact circles, conforming interface,
// positive Jacobians, and bad parameters rejected.
#include <gtest/gtest.h>

#include <cmath>

#include "isospring/geometry/construction.hpp"
#include "isospring/geometry/measure.hpp"
#include "isospring/geometry/plate_with_central_hole.hpp"
#include "isospring/geometry/specimen_shoulder.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::geometry {
namespace {

// Anton et al.'s simplified dog-bone (mm): test section 80 x 20 with a hole of radius 4, 5 mm
// straight, fillets of radius 25 widening to 30.
const double kLength = 80, kWidth = 20, kHole = 4;
const SpecimenShoulder kShoulder{5, 25, 30};

Patches specimen() {
  return add_specimen_shoulder(plate_with_central_hole(kLength, kWidth, kHole), kWidth, kShoulder);
}

TEST(SpecimenShoulder, AreaMatchesTheClosedForm) {
  const Patches patches = specimen();
  ASSERT_EQ(patches.size(), 8u);
  // Fillet region: integral over s in [0, run] of width + 2 (R - sqrt(R^2 - s^2)).
  const double R = kShoulder.fillet_radius, rise = 5,
               run = std::sqrt(R * R - (R - rise) * (R - rise));
  const double circle_part = (run * std::sqrt(R * R - run * run) + R * R * std::asin(run / R)) / 2;
  const double fillet = kWidth * run + 2 * R * run - 2 * circle_part;
  const double expected =
      kLength * kWidth - M_PI * kHole * kHole + kShoulder.straight_length * kWidth + fillet;
  EXPECT_NEAR(run, 15.0, 1e-12);
  // Exact geometry and Gauss quadrature: round-off only.
  EXPECT_NEAR(measure(patches) / expected, 1.0, 1e-12);
  for (size_t p = 0; p < patches.size(); ++p)
    EXPECT_GT(jacobian_range(patches[p], 8).min, 0.0) << "patch " << p;
}

TEST(SpecimenShoulder, FilletSidesLieOnTheirCircles) {
  const Patches patches = specimen();
  const nurbs::Patch& fillet = patches.back();
  const double R = kShoulder.fillet_radius, x0 = -kShoulder.straight_length;
  const Eigen::Vector3d top_centre(x0, kWidth + R, 0), bottom_centre(x0, -R, 0);
  for (int i = 0; i <= 20; ++i) {
    const double v = i / 20.0;
    EXPECT_NEAR((fillet.point({1.0, v, 0.0}) - top_centre).norm(), R, 1e-12) << v;
    EXPECT_NEAR((fillet.point({0.0, v, 0.0}) - bottom_centre).norm(), R, 1e-12) << v;
  }
  // The left end: x = -(5 + 15), y from -5 to 25, straight.
  for (int i = 0; i <= 10; ++i) {
    const Eigen::Vector3d x = fillet.point({i / 10.0, 1.0, 0.0});
    EXPECT_NEAR(x.x(), -20.0, 1e-12);
    EXPECT_GE(x.y(), -5.0 - 1e-12);
    EXPECT_LE(x.y(), 25.0 + 1e-12);
  }
  EXPECT_NEAR(fillet.point({0.0, 1.0, 0.0}).y(), -5.0, 1e-12);
  EXPECT_NEAR(fillet.point({1.0, 1.0, 0.0}).y(), 25.0, 1e-12);
  // Tangent to the test section's side where it starts: dy/dx = 0 at v = 0 (checked by a
  // central difference of the top side).
  const double h = 1e-6;
  const Eigen::Vector3d a = fillet.point({1.0, 0.0, 0.0}), b = fillet.point({1.0, h, 0.0});
  EXPECT_LT(std::abs((b.y() - a.y()) / (b.x() - a.x())), 1e-5);
}

TEST(SpecimenShoulder, InterfacesConformAsCurves) {
  const Patches patches = specimen();
  for (int i = 0; i <= 10; ++i) {
    const double t = i / 10.0;
    // Test section's end (patch 0, v = 1) = straight run's start; its end = the fillet's start.
    EXPECT_LT((patches[0].point({t, 1.0, 0.0}) - patches[6].point({t, 0.0, 0.0})).norm(), 1e-13);
    EXPECT_LT((patches[6].point({t, 1.0, 0.0}) - patches[7].point({t, 0.0, 0.0})).norm(), 1e-13);
  }
  // Same control points and weights on the shared sides (what the DOF map glues).
  for (int i = 0; i < 3; ++i) {
    EXPECT_LT((patches[6].control_points()[static_cast<size_t>(3 + i)] -
               patches[7].control_points()[static_cast<size_t>(i)])
                  .norm(),
              1e-14);
    EXPECT_NEAR(patches[6].weights()[static_cast<size_t>(3 + i)],
                patches[7].weights()[static_cast<size_t>(i)], 1e-15);
  }
}

TEST(SpecimenShoulder, WithoutStraightRunOnlyTheFilletIsAdded) {
  const Patches patches = add_specimen_shoulder(plate_with_central_hole(kLength, kWidth, kHole),
                                                kWidth, {0.0, 25.0, 30.0});
  ASSERT_EQ(patches.size(), 7u);
  // A quarter circle (rise = R) is the limit that still works.
  const Patches quarter = add_specimen_shoulder(plate_with_central_hole(kLength, kWidth, kHole),
                                                kWidth, {2.0, 5.0, 30.0});
  EXPECT_GT(jacobian_range(quarter.back(), 8).min, 0.0);
  EXPECT_NEAR(quarter.back().point({1.0, 1.0, 0.0}).x(), -7.0, 1e-12);
}

TEST(SpecimenShoulder, RejectsBadParameters) {
  const Patches plate = plate_with_central_hole(kLength, kWidth, kHole);
  EXPECT_THROW(add_specimen_shoulder(plate, kWidth, {5, 25, 20}),
               nurbs::InputError);                                                    // no widening
  EXPECT_THROW(add_specimen_shoulder(plate, kWidth, {5, 4, 30}), nurbs::InputError);  // R < rise
  EXPECT_THROW(add_specimen_shoulder(plate, kWidth, {-1, 25, 30}), nurbs::InputError);
  EXPECT_THROW(add_specimen_shoulder(plate, kWidth, {5, 0, 30}), nurbs::InputError);
  EXPECT_THROW(add_specimen_shoulder(plate, kWidth, {5, 25, NAN}), nurbs::InputError);
}

}  // namespace
}  // namespace isospring::geometry
