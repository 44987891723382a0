// Which patch sides lie inside the model (not on its physical surface): interfaces glued between
// patches, seams of closed patches, collapsed sides (axes, poles). Checked on models whose surface
// is known by construction.
#include <gtest/gtest.h>

#include "isospring/analysis/dof_map.hpp"
#include "isospring/analysis/sides.hpp"
#include "isospring/geometry/primitives.hpp"

namespace isospring::analysis {
namespace {

using Flags = std::array<bool, 6>;  // [2 * dir + end]

std::vector<Flags> inner_of(const std::vector<nurbs::Patch>& patches) {
  Problem problem;
  problem.patches = patches;
  return inner_sides(patches, DofMap(problem));
}

// A lone box: all six faces are its surface.
TEST(InnerSides, BoxHasNone) {
  EXPECT_EQ(inner_of(geometry::box(1, 2, 3)), std::vector<Flags>{Flags{}});
}

// Two unit cubes side by side along x share the face x = 1: the first cube's (u, end 1) and the
// second's (u, end 0); the other ten faces are outer.
TEST(InnerSides, InterfaceOfTwoCubes) {
  const nurbs::Patch a = geometry::box(1, 1, 1)[0];
  nurbs::Patch b = a;
  for (int i = 0; i < b.num_points(); ++i)
    b.set_control_point(i, a.control_point(i) + Eigen::Vector3d(1, 0, 0));
  const std::vector<Flags> inner = inner_of({a, b});
  EXPECT_EQ(inner[0], (Flags{false, true, false, false, false, false}));
  EXPECT_EQ(inner[1], (Flags{true, false, false, false, false, false}));
}

// Two cubes touching along an edge only (offset (1, 1, 0)) share 2 nodes, no face.
TEST(InnerSides, CubesTouchingAlongAnEdgeShareNoFace) {
  const nurbs::Patch a = geometry::box(1, 1, 1)[0];
  nurbs::Patch b = a;
  for (int i = 0; i < b.num_points(); ++i)
    b.set_control_point(i, a.control_point(i) + Eigen::Vector3d(1, 1, 0));
  EXPECT_EQ(inner_of({a, b}), std::vector<Flags>(2, Flags{}));
}

// The solid torus is closed in the revolution direction u: its two u faces are the seam; the
// cross-section disk's four sides (v, w) make up the torus surface.
TEST(InnerSides, TorusSeam) {
  EXPECT_EQ(inner_of(geometry::solid_torus(1.0, 0.25)),
            (std::vector<Flags>{Flags{true, true, false, false, false, false}}));
}

// The solid prolate spheroid (u revolution, v pole to pole, w axis to surface): the u faces are
// the seam, the v faces collapse to the poles, w = 0 collapses to the axis (inside the solid).
// Only w = 1 is the surface.
TEST(InnerSides, SpheroidSurfaceIsTheOuterShellOnly) {
  EXPECT_EQ(inner_of(geometry::prolate_spheroid(1.0, 0.5)),
            (std::vector<Flags>{Flags{true, true, true, true, true, false}}));
}

}  // namespace
}  // namespace isospring::analysis
