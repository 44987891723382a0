// place_markers (through geometry::PointLocator's CGAL trees) against the plain closest point:
// nurbs::invert_point on every patch from its own sampled start. Same patch, same point and a
// distance at round-off for markers on the model; the right distance for a marker off it.
#include <gtest/gtest.h>

#include <random>

#include "isospring/fitting/measure.hpp"
#include "isospring/geometry/primitives.hpp"
#include "isospring/nurbs/point_inversion.hpp"
#include "isospring/nurbs/refine.hpp"

namespace isospring::fitting {
namespace {

std::vector<nurbs::Patch> refined(std::vector<nurbs::Patch> patches, int degree, int elements) {
  for (auto& patch : patches)
    patch = nurbs::k_refine(patch, {degree, degree, degree}, {elements, elements, elements});
  return patches;
}

// A point of the patch at uniformly random parameters over its domain.
Eigen::Vector3d random_point(const nurbs::Patch& patch, std::mt19937& rng) {
  nurbs::Param u{0.0, 0.0, 0.0};
  for (int d = 0; d < patch.param_dim(); ++d)
    u[static_cast<size_t>(d)] =
        std::uniform_real_distribution<double>(patch.param_min(d), patch.param_max(d))(rng);
  return patch.point(u);
}

Marker at(const Eigen::Vector3d& x) {
  Marker m;
  m.position = x;
  m.load_case = "L1";
  return m;
}

// The smallest distance over every patch, each inverted from invert_point's sampled start.
double plain_distance(const std::vector<nurbs::Patch>& patches, const Eigen::Vector3d& x) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& patch : patches) best = std::min(best, nurbs::invert_point(patch, x).distance);
  return best;
}

void expect_placed_on_model(const std::vector<nurbs::Patch>& patches,
                            const std::vector<Marker>& markers, double size) {
  const PlacementResult placed = place_markers(patches, markers, 1e-9 * size);
  ASSERT_EQ(placed.placements.size(), markers.size());
  EXPECT_TRUE(placed.outside.empty());
  for (size_t m = 0; m < markers.size(); ++m) {
    const MarkerPlacement& p = placed.placements[m];
    ASSERT_GE(p.patch, 0);
    // The parameters reproduce the marker: the placement is exact, not a nearby sample.
    const Eigen::Vector3d x = patches[static_cast<size_t>(p.patch)].point(p.param);
    EXPECT_LT((x - markers[m].position).norm(), 1e-12 * size) << "marker " << m;
    EXPECT_LT(p.distance, 1e-12 * size);
  }
}

TEST(PlaceMarkers, PlateWithHoleMarkersLandWhereTheyAre) {
  // Two refined patches (degree 3, 16 x 16 elements each); markers at random parameters.
  const auto patches = refined(geometry::plate_with_hole_quarter_two_patch(1.0, 4.0), 3, 16);
  std::mt19937 rng(11);
  std::vector<Marker> markers;
  for (int k = 0; k < 300; ++k)
    markers.push_back(at(random_point(patches[static_cast<size_t>(k % 2)], rng)));
  expect_placed_on_model(patches, markers, 4.0);
}

TEST(PlaceMarkers, MarkersInsideARefinedVolume) {
  // The tube sector (curved, degree 3, 6 elements per direction): interior points start at the
  // nearest interior sample.
  const auto patches = refined(geometry::tube_sector(1.0, 1.5, 2.0), 3, 6);
  std::mt19937 rng(12);
  std::vector<Marker> markers;
  for (int k = 0; k < 200; ++k) markers.push_back(at(random_point(patches[0], rng)));
  expect_placed_on_model(patches, markers, 2.5);
}

TEST(PlaceMarkers, OffTheModelDistancesMatchThePlainClosestPoint) {
  const auto patches = refined(geometry::tube_sector(1.0, 1.5, 2.0), 3, 4);
  const std::vector<Marker> markers{at({2.0, 0.3, 1.0}),   // outside the outer wall
                                    at({0.5, 0.5, 1.0}),   // in the bore
                                    at({1.2, 0.2, -0.1}),  // below the end
                                    at({1.2, 0.2, 1.0})};  // inside
  const PlacementResult placed = place_markers(patches, markers, 1e-9);
  EXPECT_EQ(placed.outside, (std::vector<int>{0, 1, 2}));
  for (size_t m = 0; m < markers.size(); ++m)
    EXPECT_NEAR(placed.placements[m].distance, plain_distance(patches, markers[m].position), 1e-10)
        << "marker " << m;
  // Closed forms: radial gaps to the walls, the axial gap to the end.
  EXPECT_NEAR(placed.placements[0].distance, std::hypot(2.0, 0.3) - 1.5, 1e-10);
  EXPECT_NEAR(placed.placements[1].distance, 1.0 - std::hypot(0.5, 0.5), 1e-10);
  EXPECT_NEAR(placed.placements[2].distance, 0.1, 1e-10);
}

TEST(PlaceMarkers, SharedPositionsArePlacedOnce) {
  const auto patches = refined(geometry::plate_with_hole_quarter_two_patch(1.0, 4.0), 2, 4);
  Marker a = at({-3.0, 2.0, 0.0}), b = a;
  b.load_case = "L2";
  const PlacementResult placed = place_markers(patches, {a, b}, 1e-9);
  ASSERT_EQ(placed.placements.size(), 2u);
  EXPECT_EQ(placed.placements[0].patch, placed.placements[1].patch);
  EXPECT_EQ(placed.placements[0].param, placed.placements[1].param);
}

}  // namespace
}  // namespace isospring::fitting
