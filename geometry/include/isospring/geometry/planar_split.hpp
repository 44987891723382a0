#pragma once
// A planar region bounded by closed loops of NURBS curves (an outline and holes) cut into
// conforming four-sided NURBS patches whose outer boundaries are the given curves, unchanged.
//
// Layout (the plate_with_central_hole layout, generalised): every hole gets a square around it
// (as large as the outline and the other holes allow, neighbours sharing the room in proportion
// to their sizes),
// cut into four ring patches, each the ruled surface (in homogeneous coordinates, so exact for
// rational arcs) between a quarter of the hole loop and one side of the square; the quarters are
// cut on the rays from the hole's centre through the square's corners. The outline must be a
// polygon of axis-parallel edges (after a rotation that aligns its first edge with x); the lines
// through its corners and through the squares' sides form a tensor grid, and every grid cell
// inside the outline that is not a hole square is a rectangle. All patches of a grid column share
// one knot vector along x, all of a grid row one along y (the union of the knots of the hole
// quarters there, same degree everywhere), so neighbouring patches have identical control points
// and weights on their common side: the multipatch analysis glues them (C0). An outline that is
// one closed curve without holes (a disk, an ellipse) becomes a central square and four ring
// patches out to the curve. Every patch is right-handed (positive Jacobian) in the xy plane.
#include <vector>

#include "isospring/nurbs/patch.hpp"

namespace isospring::geometry {

/// Closed loops of curves (param_dim 1) in the plane z = 0, each loop in order around the region
/// (either sense; the ends of consecutive curves meet within `tolerance`).
struct PlanarRegion {
  std::vector<nurbs::Patch> outline;
  std::vector<std::vector<nurbs::Patch>> holes;
};

/// The conforming patches of the region (see above), in grid order (rows bottom to top, columns
/// left to right; four ring patches in place of a hole's square: below, right, above, left of
/// the hole). `tolerance` is the length below which points and coordinates are the same.
/// Throws std::invalid_argument saying why the region cannot be split this way: an outline with
/// slanted or curved edges around holes, a hole that is not star-shaped about its centre, a hole
/// too close to the outline or to another hole for a ring of patches, an outline corner in line
/// with a hole's centre, a folded patch.
std::vector<nurbs::Patch> split_planar_region(const PlanarRegion& region, double tolerance);

}  // namespace isospring::geometry
