// A planar region with holes -> conforming four-sided NURBS patches (see planar_split.hpp): the
// stages of the split, built on the ring construction (planar_split_parts.hpp).
#include "isospring/geometry/planar_split.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>

#include "isospring/geometry/construction.hpp"
#include "planar_split_parts.hpp"

namespace isospring::geometry {

namespace {

using Eigen::Vector3d;
using nurbs::KnotVector;
using nurbs::Patch;
using namespace planar_split_detail;

// The region as the stages build it up, in the frame of its grid (the outline's first edge along
// x). Invariant: when `polygon` is false the outline is a disk and `rings` holds one ring, the
// outline itself (hole = false), and `corners` is empty.
struct PlanarLayout {
  bool polygon = false;  // the outline is straight edges, parallel or normal to each other
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // region -> grid frame
  std::vector<Vector3d> corners;                           // the outline's, in the grid frame
  std::vector<Ring> rings;                                 // one per hole, in order
  std::vector<double> gx, gy;                              // the grid lines
  std::vector<KnotVector> col_knots, row_knots;            // per grid column and row
};

std::vector<Ring*> ring_pointers(std::vector<Ring>& rings) {
  std::vector<Ring*> pointers;
  for (Ring& ring : rings) pointers.push_back(&ring);
  return pointers;
}

std::string ring_name(const Ring& ring, size_t h) {
  return ring.hole ? hole_name(h) : "the outline";
}

// The holes as rings, their loops counter-clockwise.
std::vector<Ring> hole_rings(const PlanarRegion& region) {
  std::vector<Ring> rings;
  for (const Loop& hole : region.holes) {
    if (hole.empty()) refuse("a hole has no curves");
    Ring ring;
    ring.loop = counter_clockwise(hole);
    rings.push_back(ring);
  }
  return rings;
}

// A polygonal outline: the rotation aligning its first edge with x (the grid is axis-parallel),
// its corners in that frame, and the holes rotated with it. Refuses slanted edges and outlines
// of fewer than 4 corners.
void align_polygon(const Loop& outline, double tolerance, PlanarLayout& layout) {
  const Vector3d d = end_point(outline.front()) - start_point(outline.front());
  layout.rotation =
      Eigen::AngleAxisd(-std::atan2(d.y(), d.x()), Vector3d::UnitZ()).toRotationMatrix();
  std::vector<Vector3d> corners;
  for (const Patch& c : outline) corners.push_back(layout.rotation * start_point(c));
  // Corners between collinear edges are no corners.
  std::vector<Vector3d> kept;
  for (size_t i = 0; i < corners.size(); ++i) {
    const Vector3d& prev = corners[(i + corners.size() - 1) % corners.size()];
    const Vector3d& next = corners[(i + 1) % corners.size()];
    const Vector3d a = corners[i] - prev, b = next - corners[i];
    if (std::abs(a.x() * b.y() - a.y() * b.x()) > tolerance * (a.norm() + b.norm()))
      kept.push_back(corners[i]);
  }
  corners = kept;
  for (size_t i = 0; i < corners.size(); ++i) {
    const Vector3d e = corners[(i + 1) % corners.size()] - corners[i];
    if (std::abs(e.x()) > tolerance && std::abs(e.y()) > tolerance)
      refuse(
          "the outline has a slanted edge (not parallel to its first edge or normal to it); "
          "only outlines of parallel and perpendicular straight edges are cut into "
          "rectangles");
  }
  if (corners.size() < 4) refuse("the outline has fewer than 4 corners");
  layout.corners = corners;
  for (Ring& ring : layout.rings)
    for (Patch& c : ring.loop) c = transformed(c, layout.rotation);
}

// The (counter-clockwise) outline as the polygon of the grid or, when curved and without holes,
// as the one ring of a disk; then every ring's centre and extent.
void outline_frame(const Loop& outline, double tolerance, PlanarLayout& layout) {
  layout.polygon = std::all_of(outline.begin(), outline.end(),
                               [&](const Patch& c) { return straight(c, tolerance); });
  if (layout.polygon) {
    align_polygon(outline, tolerance, layout);
  } else {
    if (!layout.rings.empty())
      refuse(
          "the outline has curved edges and the face has holes; only polygonal outlines "
          "(straight edges parallel or normal to each other) are cut around holes");
    Ring disk;
    disk.loop = outline;
    disk.hole = false;
    layout.rings.push_back(disk);
  }
  for (Ring& ring : layout.rings) prepare_ring(ring);
}

// Half side of each hole's square: as large as the outline allows (no outline corner's line
// inside it); two holes apart by d along an axis share d in proportion to their sizes (so
// neither square reaches a line of the other: s_h + s_k <= d); holes on one line (same centre
// x or y) need the same half side, or one's lines would cross the other's square. A disk's
// square has half the inner radius.
void size_squares(double tolerance, PlanarLayout& layout) {
  std::vector<Ring>& rings = layout.rings;
  if (!layout.polygon) rings[0].half = rings[0].extent / 2.0;
  for (size_t h = 0; h < rings.size() && layout.polygon; ++h) {
    const Vector3d& c = rings[h].center;
    for (const Vector3d& v : layout.corners)
      for (int axis = 0; axis < 2; ++axis) {
        const double d = std::abs(v[axis] - c[axis]);
        if (d <= tolerance)
          refuse("a corner of the outline is in line with the centre of " + hole_name(h) +
                 " (a cut line would cross the hole)");
        rings[h].half = std::min(rings[h].half, d);
      }
    for (size_t k = 0; k < rings.size(); ++k) {
      if (k == h) continue;
      const Vector3d d = (rings[k].center - c).cwiseAbs();
      if (d.x() <= tolerance && d.y() <= tolerance)
        refuse(hole_name(h) + " and " + hole_name(k) + " have the same centre");
      const double share = rings[h].extent / (rings[h].extent + rings[k].extent);
      for (int axis = 0; axis < 2; ++axis)
        if (d[axis] > tolerance) rings[h].half = std::min(rings[h].half, share * d[axis]);
    }
  }
  share_squares_in_line(ring_pointers(rings), [&](size_t h, size_t k) {
    const Vector3d d = (rings[k].center - rings[h].center).cwiseAbs();
    return d.x() <= tolerance || d.y() <= tolerance;
  });
  for (size_t h = 0; h < rings.size() && layout.polygon; ++h)
    check_ring_room(rings[h], hole_name(h), "the outline");
}

// The grid: outline corners and square sides.
void grid_lines(double tolerance, PlanarLayout& layout) {
  std::vector<double> xs, ys;
  for (const Vector3d& v : layout.corners) {
    xs.push_back(v.x());
    ys.push_back(v.y());
  }
  for (const Ring& ring : layout.rings) {
    xs.push_back(ring.center.x() - ring.half);
    xs.push_back(ring.center.x() + ring.half);
    ys.push_back(ring.center.y() - ring.half);
    ys.push_back(ring.center.y() + ring.half);
  }
  layout.gx = merged(xs, tolerance);
  layout.gy = merged(ys, tolerance);
}

// Each ring in its grid cell (inside the outline), its loop cut into quarters on the square.
void place_rings(double tolerance, PlanarLayout& layout) {
  for (size_t h = 0; h < layout.rings.size(); ++h) {
    Ring& ring = layout.rings[h];
    const std::string what = ring_name(ring, h);
    place_ring(ring, layout.gx, layout.gy, tolerance, what, "line");
    if (layout.polygon && !inside_polygon(layout.corners, ring.center))
      refuse(what + " is not inside the outline");
    const Square square = grid_square(ring, layout.gx, layout.gy);
    cut_quarters(ring, square.x0, square.x1, square.y0, square.y1, what);
  }
}

// One degree everywhere, and per grid column (row) the union of the knots of the quarters that
// run along it, so every shared side has the same knots on both patches.
void grid_knots(PlanarLayout& layout) {
  const int degree = ring_degree(ring_pointers(layout.rings));
  layout.col_knots.resize(layout.gx.size() - 1);
  layout.row_knots.resize(layout.gy.size() - 1);
  for (int axis = 0; axis < 2; ++axis) {
    const size_t cells = axis == 0 ? layout.gx.size() - 1 : layout.gy.size() - 1;
    for (size_t i = 0; i < cells; ++i) {
      std::vector<Patch*> quarters;
      for (Ring& ring : layout.rings)
        add_quarters_along(ring, axis == 0, axis == 1, static_cast<int>(i), quarters);
      (axis == 0 ? layout.col_knots : layout.row_knots)[i] = common_knots(quarters, degree);
    }
  }
}

// The patches cell by cell (x fastest): a ring's four patches (and a disk's centre rectangle),
// or a rectangle where the cell is inside the outline.
std::vector<Patch> grid_patches(const PlanarLayout& layout) {
  const std::vector<double>& gx = layout.gx;
  const std::vector<double>& gy = layout.gy;
  std::vector<Patch> patches;
  for (size_t j = 0; j + 1 < gy.size(); ++j)
    for (size_t i = 0; i + 1 < gx.size(); ++i) {
      const KnotVector &along_x = layout.col_knots[i], &along_y = layout.row_knots[j];
      const auto ring = std::find_if(layout.rings.begin(), layout.rings.end(), [&](const Ring& r) {
        return r.col == static_cast<int>(i) && r.row == static_cast<int>(j);
      });
      if (ring != layout.rings.end()) {
        const std::string what = ring_name(*ring, static_cast<size_t>(ring - layout.rings.begin()));
        for (Patch& p :
             square_ring_patches(*ring, grid_square(*ring, gx, gy), along_x, along_y, what))
          patches.push_back(std::move(p));
        if (!ring->hole)
          patches.push_back(rectangle(gx[i], gx[i + 1], gy[j], gy[j + 1], along_x, along_y));
        continue;
      }
      const Vector3d bl(gx[i], gy[j], 0), tr(gx[i + 1], gy[j + 1], 0);
      if (!layout.polygon || !inside_polygon(layout.corners, (bl + tr) / 2.0)) continue;
      patches.push_back(rectangle(gx[i], gx[i + 1], gy[j], gy[j + 1], along_x, along_y));
    }
  return patches;
}

}  // namespace

// The stages in order: the holes' rings, the outline's frame, the squares, the grid, the rings in
// their cells, the knots, the patches, back in the region's frame.
std::vector<Patch> split_planar_region(const PlanarRegion& region, double tolerance) {
  if (region.outline.empty()) refuse("the region has no outline");
  const Loop outline = counter_clockwise(region.outline);
  PlanarLayout layout;
  layout.rings = hole_rings(region);
  outline_frame(outline, tolerance, layout);
  size_squares(tolerance, layout);
  grid_lines(tolerance, layout);
  place_rings(tolerance, layout);
  grid_knots(layout);
  std::vector<Patch> patches = grid_patches(layout);
  const Eigen::Matrix3d back = layout.rotation.transpose();
  for (Patch& p : patches) p = transformed(p, back);
  return patches;
}

}  // namespace isospring::geometry
