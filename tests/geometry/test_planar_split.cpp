// split_planar_region: planar regions with holes cut into conforming 4-sided patches, checked
// against closed-form areas and perimeters, Jacobian signs and side-by-side conformity.
#include "isospring/geometry/planar_split.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "isospring/geometry/construction.hpp"
#include "isospring/geometry/measure.hpp"
#include "planar_split_checks.hpp"

namespace isospring::geometry {
namespace {

using Eigen::Vector3d;

nurbs::Patch segment(const Vector3d& a, const Vector3d& b) {
  return nurbs::Patch({nurbs::KnotVector(1, {0, 0, 1, 1})}, {a, b});
}

std::vector<nurbs::Patch> polygon(const std::vector<Vector3d>& corners) {
  std::vector<nurbs::Patch> loop;
  for (size_t i = 0; i < corners.size(); ++i)
    loop.push_back(segment(corners[i], corners[(i + 1) % corners.size()]));
  return loop;
}

double min_jacobian(const std::vector<nurbs::Patch>& patches) {
  double m = 1e300;
  for (const auto& p : patches) m = std::min(m, jacobian_range(p, 6).min);
  return m;
}

TEST(PlanarSplit, SquareWithCentralHoleIsFourRingPatches) {
  PlanarRegion region;
  region.outline = polygon({{0, 0, 0}, {4, 0, 0}, {4, 4, 0}, {0, 4, 0}});
  // The hole as two half circles running clockwise (as a CAD inner wire does).
  region.holes.push_back(
      {circular_arc({2, 2, 0}, 1.0, M_PI, -M_PI), circular_arc({2, 2, 0}, 1.0, 0.0, -M_PI)});
  const auto patches = split_planar_region(region, 1e-12);
  ASSERT_EQ(patches.size(), 4u);
  EXPECT_NEAR(measure(patches) / (16.0 - M_PI), 1.0, 1e-14);
  EXPECT_GT(min_jacobian(patches), 0.0);
  EXPECT_NEAR(test::unshared_side_length(patches, 1e-12) / (16.0 + 2 * M_PI), 1.0, 1e-12);
  // The hole boundary is exact: points of the inner sides lie on the circle.
  for (const auto& p : patches)
    for (double t : {0.1, 0.37, 0.5, 0.93}) {
      const Vector3d x = p.point({t, 0.0, 0});
      EXPECT_NEAR((x - Vector3d(2, 2, 0)).norm(), 1.0, 1e-14);
    }
}

TEST(PlanarSplit, PlateWithTwoHolesConforms) {
  // Plate 180 x 150 with two holes of radius 5 (examples/cad/plate_with_holes.step, mm).
  PlanarRegion region;
  region.outline = polygon({{0, 0, 0}, {180, 0, 0}, {180, 150, 0}, {0, 150, 0}});
  for (double x : {25.0, 155.0})
    region.holes.push_back({circular_arc({x, 75, 0}, 5.0, 0.3, 2 * M_PI)});
  const auto patches = split_planar_region(region, 1e-9);
  // Grid x: 0, 25 +- 25 = 50, 155 +- 25 = 130, 180 (the squares touch the left and right edges);
  // y: 0, 50, 100, 150: 3 x 3 cells, two of them hole squares (4 patches each).
  EXPECT_EQ(patches.size(), 7u + 8u);
  EXPECT_NEAR(measure(patches) / (180.0 * 150.0 - 2 * 25 * M_PI), 1.0, 1e-13);
  EXPECT_GT(min_jacobian(patches), 0.0);
  EXPECT_NEAR(test::unshared_side_length(patches, 1e-9) / (2 * 330.0 + 2 * 10 * M_PI), 1.0, 1e-12);
}

TEST(PlanarSplit, HolesOfDifferentSizesGetSquaresOfTheirOwn) {
  // Plate 100 x 60, hole of radius 10 at (30, 30) and of radius 2 at (90, 10): 20 apart in y,
  // they share that room 10 : 2 (squares of half side 16.7 and 3.3); one square for both
  // (at most 10, the small hole's distance to the outline) would leave no room for the big one.
  PlanarRegion region;
  region.outline = polygon({{0, 0, 0}, {100, 0, 0}, {100, 60, 0}, {0, 60, 0}});
  region.holes.push_back({circular_arc({30, 30, 0}, 10.0, 0.0, 2 * M_PI)});
  region.holes.push_back({circular_arc({90, 10, 0}, 2.0, 0.0, 2 * M_PI)});
  const auto patches = split_planar_region(region, 1e-9);
  EXPECT_NEAR(measure(patches) / (6000.0 - 104 * M_PI), 1.0, 1e-13);
  EXPECT_GT(min_jacobian(patches), 0.0);
  EXPECT_NEAR(test::unshared_side_length(patches, 1e-9) / (320.0 + 24 * M_PI), 1.0, 1e-12);
}

TEST(PlanarSplit, LShapeIsRectangles) {
  PlanarRegion region;
  region.outline = polygon({{0, 0, 0}, {5, 0, 0}, {5, 1, 0}, {1, 1, 0}, {1, 6, 0}, {0, 6, 0}});
  const auto patches = split_planar_region(region, 1e-12);
  EXPECT_EQ(patches.size(), 3u);
  EXPECT_NEAR(measure(patches), 10.0, 1e-13);
  EXPECT_GT(min_jacobian(patches), 0.0);
  EXPECT_NEAR(test::unshared_side_length(patches, 1e-12), 22.0, 1e-12);
}

TEST(PlanarSplit, RotatedOutlineAndDisk) {
  // A square turned by 30 degrees with an off-centre hole, and a disk (one closed circle).
  const double c = std::cos(M_PI / 6), s = std::sin(M_PI / 6);
  auto at = [&](double x, double y) { return Vector3d(c * x - s * y, s * x + c * y, 0); };
  PlanarRegion region;
  region.outline = polygon({at(0, 0), at(3, 0), at(3, 2), at(0, 2)});
  region.holes.push_back({circular_arc(at(1, 1), 0.5, 0.0, 2 * M_PI)});
  const auto plate = split_planar_region(region, 1e-12);
  EXPECT_NEAR(measure(plate) / (6.0 - M_PI / 4), 1.0, 1e-13);
  EXPECT_GT(min_jacobian(plate), 0.0);
  EXPECT_NEAR(test::unshared_side_length(plate, 1e-12) / (10.0 + M_PI), 1.0, 1e-12);

  PlanarRegion disk;
  disk.outline = {circular_arc({1, 2, 0}, 3.0, 0.0, 2 * M_PI)};
  const auto five = split_planar_region(disk, 1e-12);
  EXPECT_EQ(five.size(), 5u);
  EXPECT_NEAR(measure(five) / (9 * M_PI), 1.0, 1e-13);
  EXPECT_GT(min_jacobian(five), 0.0);
  EXPECT_NEAR(test::unshared_side_length(five, 1e-12) / (6 * M_PI), 1.0, 1e-12);
}

TEST(PlanarSplit, RefusesWhatItCannotCut) {
  auto message = [](const PlanarRegion& region) {
    try {
      split_planar_region(region, 1e-12);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  PlanarRegion triangle;
  triangle.outline = polygon({{0, 0, 0}, {4, 0, 0}, {0, 4, 0}});
  triangle.holes.push_back({circular_arc({1, 1, 0}, 0.3, 0.0, 2 * M_PI)});
  EXPECT_NE(message(triangle).find("slanted edge"), std::string::npos) << message(triangle);
  PlanarRegion crowded;
  crowded.outline = polygon({{0, 0, 0}, {4, 0, 0}, {4, 4, 0}, {0, 4, 0}});
  crowded.holes.push_back({circular_arc({1.05, 2, 0}, 1.0, 0.0, 2 * M_PI)});
  EXPECT_NE(message(crowded).find("hole 1 (half size 1) is too close"), std::string::npos)
      << message(crowded);
  PlanarRegion rounded;  // curved outline around a hole
  rounded.outline = {circular_arc({0, 0, 0}, 3.0, 0.0, 2 * M_PI)};
  rounded.holes.push_back({circular_arc({0, 0, 0}, 1.0, 0.0, 2 * M_PI)});
  EXPECT_NE(message(rounded).find("curved edges and the face has holes"), std::string::npos);
}

}  // namespace
}  // namespace isospring::geometry
