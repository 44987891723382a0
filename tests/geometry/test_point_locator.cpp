// PointLocator against analytic closest points on a disk, a cylinder and a sphere sector.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "isospring/geometry/construction.hpp"
#include "isospring/geometry/point_locator.hpp"
#include "isospring/geometry/primitives.hpp"

namespace isospring::geometry {
namespace {

// Inversion converges to 1e-12 of the model size; 1e-10 absolute on unit-size models leaves
// margin for the conditioning of the closest-point problem.
constexpr double kTolerance = 1e-10;

TEST(PointLocator, DiskInPlaneAndAbove) {
  const Patches disk = disk_five_patch(1.0);
  const PointLocator locator(disk);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> angle(0.0, 2 * M_PI), unit(0.0, 1.0);
  for (int n = 0; n < 50; ++n) {
    const double t = angle(rng), r = 1.6 * unit(rng), z = unit(rng) - 0.5;
    const Eigen::Vector3d x(r * std::cos(t), r * std::sin(t), z);
    const Eigen::Vector3d expected =
        r <= 1.0 ? Eigen::Vector3d(x.x(), x.y(), 0) : Eigen::Vector3d(std::cos(t), std::sin(t), 0);
    const Location loc = locator.locate(x);
    ASSERT_GE(loc.patch, 0);
    EXPECT_LT((loc.point - expected).norm(), kTolerance) << "r " << r << " t " << t;
    EXPECT_NEAR(loc.distance, (expected - x).norm(), kTolerance);
    EXPECT_LT((disk[static_cast<size_t>(loc.patch)].point(loc.param) - loc.point).norm(), 1e-15);
    EXPECT_FALSE(loc.inside);
  }
}

TEST(PointLocator, CylinderSurfaceAndTubeVolume) {
  // Quarter cylinder surface r = 1.5, z in [0, 2], and the tube 1 <= r <= 2 around it.
  const nurbs::Patch surface =
      extrude(circular_arc(Eigen::Vector3d::Zero(), 1.5, 0.0, M_PI / 2), Eigen::Vector3d(0, 0, 2));
  const PointLocator on_surface({surface});
  const Patches tube = tube_sector(1.0, 2.0, 2.0);
  const PointLocator in_tube(tube);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> angle(0.05, M_PI / 2 - 0.05), radius(0.3, 3.0),
      height(0.05, 1.95);
  for (int n = 0; n < 40; ++n) {
    const double t = angle(rng), r = radius(rng), z = height(rng);
    const Eigen::Vector3d x(r * std::cos(t), r * std::sin(t), z);
    const Location s = on_surface.locate(x);
    EXPECT_NEAR(s.distance, std::abs(r - 1.5), kTolerance);
    EXPECT_LT((s.point - Eigen::Vector3d(1.5 * std::cos(t), 1.5 * std::sin(t), z)).norm(),
              kTolerance);
    const Location v = in_tube.locate(x);
    const double expected = r < 1.0 ? 1.0 - r : (r > 2.0 ? r - 2.0 : 0.0);
    EXPECT_NEAR(v.distance, expected, kTolerance) << "r " << r;
    EXPECT_EQ(v.inside, expected == 0.0) << "r " << r;
    if (expected == 0.0) {
      EXPECT_LT((tube[0].point(v.param) - x).norm(), kTolerance);
    }
  }
}

TEST(PointLocator, SphereSectorOutsidePointsAndFarReport) {
  const Patches shell = hollow_sphere_sector(1.0, 2.0);
  const PointLocator locator(shell);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> polar(0.1, M_PI / 2 - 0.1), azimuth(0.1, M_PI / 2 - 0.1),
      radius(2.05, 3.0);
  std::vector<Eigen::Vector3d> points;
  for (int n = 0; n < 30; ++n) {
    const double th = polar(rng), ph = azimuth(rng), r = radius(rng);
    const Eigen::Vector3d dir(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph),
                              std::cos(th));
    const Location loc = locator.locate(r * dir);
    EXPECT_NEAR(loc.distance, r - 2.0, kTolerance);
    EXPECT_LT((loc.point - 2.0 * dir).norm(), kTolerance);
    points.push_back(r * dir);
  }
  points.push_back(Eigen::Vector3d(1.0, 0.5, 0.5));  // inside the shell
  const PointLocator::Batch batch = locator.locate_all(points, 0.5);
  for (int i : batch.far) EXPECT_GT(points[static_cast<size_t>(i)].norm(), 2.5);
  EXPECT_TRUE(batch.locations.back().inside);
  int expected_far = 0;
  for (const auto& p : points) expected_far += p.norm() - 2.0 > 0.5;
  EXPECT_EQ(static_cast<int>(batch.far.size()), expected_far);
}

}  // namespace
}  // namespace isospring::geometry
