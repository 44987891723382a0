// conform_shared_sides: neighbouring faces cut independently get common knots on their shared
// straight sides, without any change to the geometry.
#include <gtest/gtest.h>

#include "isospring/geometry/conforming_sides.hpp"
#include "isospring/geometry/construction.hpp"
#include "isospring/geometry/measure.hpp"
#include "isospring/nurbs/refine.hpp"
#include "planar_split_checks.hpp"

namespace isospring::geometry {
namespace {

using Eigen::Vector3d;

// The rectangle [x0, x1] x [0, 1], bilinear.
nurbs::Patch rectangle(double x0, double x1) {
  return nurbs::Patch({nurbs::KnotVector(1, {0, 0, 1, 1}), nurbs::KnotVector(1, {0, 0, 1, 1})},
                      {{x0, 0, 0}, {x1, 0, 0}, {x0, 1, 0}, {x1, 1, 0}});
}

TEST(ConformingSides, SharedSidesGetCommonKnotsAndTheGeometryStays) {
  // Three rectangles in a row sharing x = 1 and x = 2, refined differently along y: the middle
  // one is degree 2 with a double knot at 0.5, the right one has a knot at 0.25 and its u
  // direction reversed (its shared side runs the other way). Knots must travel through the
  // middle patch to both neighbours, in both senses.
  nurbs::Patch left = rectangle(0, 1);
  nurbs::Patch middle = nurbs::insert_knot(nurbs::elevate_degree(rectangle(1, 2), 1, 1), 1, 0.5, 2);
  nurbs::Patch right = reverse_direction(nurbs::insert_knot(rectangle(2, 3), 1, 0.25), 1);
  const std::vector<nurbs::Patch> before{left, middle, right};
  EXPECT_GT(test::unshared_side_length(before, 1e-12), 8.0 + 1e-9);  // the x = 1, 2 sides differ
  const std::vector<nurbs::Patch> after = conform_shared_sides(before, 1e-12);
  ASSERT_EQ(after.size(), 3u);
  // Only the outline is unshared: 3 + 3 + 1 + 1.
  EXPECT_NEAR(test::unshared_side_length(after, 1e-12), 8.0, 1e-12);
  for (size_t p = 0; p < 3; ++p) {
    EXPECT_NEAR(measure(after[p]), 1.0, 1e-14);
    for (double u : {0.1, 0.5, 0.9})
      for (double v : {0.0, 0.3, 0.5, 1.0})
        EXPECT_LT((after[p].point({u, v, 0}) - before[p].point({u, v, 0})).norm(), 1e-14);
  }
  // Every patch is now degree 2 along y with a double knot at y = 0.25 (the right patch's C0
  // knot of degree 1 stays C0 when elevated) and at y = 0.5 (the middle one's); the right
  // patch's y runs downwards, so y = 0.25 is its parameter 0.75.
  for (size_t p = 0; p < 3; ++p) {
    EXPECT_EQ(after[p].degree(1), 2);
    EXPECT_EQ(after[p].knots(1).multiplicity(p == 2 ? 0.75 : 0.25), 2) << p;
    EXPECT_EQ(after[p].knots(1).multiplicity(0.5), 2) << p;
  }
}

TEST(ConformingSides, SidesThatOnlyTouchAreLeftAlone) {
  // Corner contact and a curved side: nothing to share, nothing changes.
  const std::vector<nurbs::Patch> before{rectangle(0, 1),
                                         nurbs::insert_knot(rectangle(1, 2), 1, 0.3)};
  std::vector<nurbs::Patch> shifted = before;
  for (int i = 0; i < shifted[1].num_points(); ++i)
    shifted[1].set_control_point(i, shifted[1].control_point(i) + Vector3d(0, 1, 0));
  const std::vector<nurbs::Patch> after = conform_shared_sides(shifted, 1e-12);
  EXPECT_EQ(after[0].num_points(), 4);
  EXPECT_EQ(after[1].num_points(), shifted[1].num_points());
}

}  // namespace
}  // namespace isospring::geometry
