#pragma once
// An orthogonal solid (every planar face normal to one of three axes: L, T and U sections,
// stepped blocks) with straight through-holes along those axes, cut into conforming hexahedral
// NURBS volume patches: the planar split (planar_split.hpp) in three dimensions.
//
// Every face plane of the solid is a grid plane. Every hole gets a square around it in the plane
// of its two cross axes (as large as the grid planes and the other holes allow: neighbours share
// the room between them in proportion to their sizes, holes on one line get the same square);
// the square's sides are grid planes too. A grid cell is then either a box of the solid, or a
// slab of a hole's square, which becomes the hole's four ruled ring patches swept along the hole
// (exact: a linear sweep of the exact hole curves), or outside the solid. Every grid slab along an
// axis has one knot vector (the union of the knots of the hole quarters that run along it, one
// degree everywhere), so neighbouring cells have identical control points and weights on their
// common face and the multipatch analysis glues them (C0). Holes may run along different axes
// (the CAx-IF L-bracket: one hole through one leg, three through the other).
#include <Eigen/Core>
#include <array>
#include <functional>
#include <vector>

#include "isospring/nurbs/patch.hpp"

namespace isospring::geometry {

/// A straight hole through the solid along one of the three axes.
struct ThroughHole {
  int axis = 0;                 // 0, 1 or 2: the hole runs along this axis...
  double from = 0.0, to = 0.0;  // ...from this coordinate to that one (from < to)
  /// Closed loop of curves (param_dim 1) around the hole, in the plane of the two other axes:
  /// point (x, y, 0) is the coordinate along axis (axis + 1) % 3 and along (axis + 2) % 3.
  std::vector<nurbs::Patch> loop;
};

struct BlockRegion {
  /// Coordinates of the solid's planar faces along each axis (faces normal to that axis).
  std::array<std::vector<double>, 3> planes;
  /// Whether a point is inside the solid. Asked only at the centres of grid cells away from the
  /// holes and next to a hole's loop, where a grid cell is wholly inside or outside.
  std::function<bool(const Eigen::Vector3d&)> inside;
  std::vector<ThroughHole> holes;
};

/// The conforming volume patches of the solid (see above), right-handed (positive Jacobian),
/// cells in grid order (axis 0 fastest), four ring patches for a hole's cell (below, right, above,
/// left of the hole in its cross plane). `tolerance` is the length below which coordinates are
/// the same. Throws std::invalid_argument saying why it cannot be cut this way: a hole whose
/// centre is in line with a face plane, a hole too close to a face or another hole for a ring of
/// patches, a grid plane crossing a hole's square, a hole not inside the solid, a folded patch.
std::vector<nurbs::Patch> split_block_region(const BlockRegion& region, double tolerance);

}  // namespace isospring::geometry
