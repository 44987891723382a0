// An orthogonal solid with through-holes -> conforming hexahedral patches (see block_split.hpp).
#include "isospring/geometry/block_split.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "isospring/geometry/coons.hpp"
#include "planar_split_parts.hpp"

namespace isospring::geometry {

namespace {

using Eigen::Vector3d;
using nurbs::KnotVector;
using nurbs::Patch;
using namespace planar_split_detail;

struct Hole {
  int axis = 0, b = 1, c = 2;  // along `axis`; its cross plane's x is axis b, y is axis c
  double from = 0.0, to = 0.0;
  Ring ring;                               // in the cross plane
  Vector3d axis_point = Vector3d::Zero();  // the centre in 3D (its `axis` coordinate unused)
  int slab0 = -1, slab1 = -1;              // grid slabs [slab0, slab1) along `axis`
  std::vector<Patch> cross_patches;        // the four ring patches in the cross plane
  std::string name;
};

// The box [lo, hi] with the given knots per axis: control points at the Greville abscissae.
Patch box(const Vector3d& lo, const Vector3d& hi, const std::array<KnotVector, 3>& knots) {
  const std::vector<double> gx = greville_abscissae(knots[0]), gy = greville_abscissae(knots[1]),
                            gz = greville_abscissae(knots[2]);
  std::vector<Vector3d> points;
  for (double w : gz)
    for (double v : gy)
      for (double u : gx)
        points.emplace_back(lerp(lo.x(), hi.x(), u), lerp(lo.y(), hi.y(), v),
                            lerp(lo.z(), hi.z(), w));
  return Patch({knots[0], knots[1], knots[2]}, points);
}

// A ring patch of the hole's cross plane swept along the hole from a0 to a1 with the given knots
// (a linear sweep: control points at the Greville abscissae, weights unchanged along it). (b, c,
// axis) is a cyclic permutation of (x, y, z), so a right-handed cross patch stays right-handed.
Patch sweep(const Patch& cross, const Hole& hole, double a0, double a1, const KnotVector& knots) {
  const std::vector<double> g = greville_abscissae(knots);
  std::vector<Vector3d> points;
  std::vector<double> weights;
  for (double t : g)
    for (int i = 0; i < cross.num_points(); ++i) {
      Vector3d x;
      x[hole.b] = cross.control_point(i).x();
      x[hole.c] = cross.control_point(i).y();
      x[hole.axis] = lerp(a0, a1, t);
      points.push_back(x);
      weights.push_back(cross.weight(i));
    }
  return Patch({cross.knots(0), cross.knots(1), knots}, points, weights);
}

bool crosses(const Hole& h, int q) {
  return h.b == q || h.c == q;
}

std::vector<Ring*> ring_pointers(std::vector<Hole>& holes) {
  std::vector<Ring*> rings;
  for (Hole& h : holes) rings.push_back(&h.ring);
  return rings;
}

// The holes with their rings (loops counter-clockwise, centres and extents) and their centres in
// 3D; refuses holes without an axis, a length or curves.
std::vector<Hole> block_holes(const BlockRegion& region, double tolerance) {
  std::vector<Hole> holes;
  for (size_t h = 0; h < region.holes.size(); ++h) {
    const ThroughHole& in = region.holes[h];
    Hole hole;
    hole.name = hole_name(h);
    if (in.axis < 0 || in.axis > 2) refuse(hole.name + " has no axis 0, 1 or 2");
    if (!(in.to - in.from > tolerance)) refuse(hole.name + " has no length");
    if (in.loop.empty()) refuse(hole.name + " has no curves");
    hole.axis = in.axis;
    hole.b = (in.axis + 1) % 3;
    hole.c = (in.axis + 2) % 3;
    hole.from = in.from;
    hole.to = in.to;
    hole.ring.loop = counter_clockwise(in.loop);
    prepare_ring(hole.ring);
    hole.axis_point[hole.b] = hole.ring.center.x();
    hole.axis_point[hole.c] = hole.ring.center.y();
    holes.push_back(hole);
  }
  return holes;
}

// Half sides of the squares: no face plane inside a square (the grid planes run through the
// whole solid); two holes apart by d along a common cross axis share d in proportion to their
// sizes; holes on one line (same coordinate on a common cross axis) get the same square. Refuses
// overlapping holes and holes without room for a ring.
void size_squares(const BlockRegion& region, double tolerance, std::vector<Hole>& holes) {
  for (Hole& h : holes) {
    for (int q : {h.b, h.c})
      for (double v : region.planes[static_cast<size_t>(q)]) {
        const double d = std::abs(v - h.axis_point[q]);
        if (d <= tolerance)
          refuse("a face of the solid is in line with the centre of " + h.name +
                 " (a cut plane would cross the hole)");
        h.ring.half = std::min(h.ring.half, d);
      }
    for (const Hole& k : holes) {
      if (&k == &h) continue;
      bool apart = false;
      for (int q = 0; q < 3; ++q) {
        if (!crosses(h, q) || !crosses(k, q)) continue;
        const double d = std::abs(k.axis_point[q] - h.axis_point[q]);
        if (d > tolerance) {
          apart = true;
          h.ring.half = std::min(h.ring.half, d * h.ring.extent / (h.ring.extent + k.ring.extent));
        }
      }
      if (!apart && k.axis == h.axis && k.from < h.to - tolerance && h.from < k.to - tolerance)
        refuse(h.name + " and " + k.name + " overlap");
    }
  }
  share_squares_in_line(ring_pointers(holes), [&](size_t i, size_t j) {
    const Hole &h = holes[i], &k = holes[j];
    for (int q = 0; q < 3; ++q)
      if (crosses(h, q) && crosses(k, q) &&
          std::abs(k.axis_point[q] - h.axis_point[q]) <= tolerance)
        return true;
    return false;
  });
  for (const Hole& h : holes) check_ring_room(h.ring, h.name, "a face");
}

// The grid planes along each axis: face planes, the squares' sides and the holes' ends.
std::array<std::vector<double>, 3> grid_planes(const BlockRegion& region,
                                               const std::vector<Hole>& holes, double tolerance) {
  std::array<std::vector<double>, 3> grid;
  for (int q = 0; q < 3; ++q) {
    std::vector<double> values = region.planes[static_cast<size_t>(q)];
    for (const Hole& h : holes) {
      if (crosses(h, q)) {
        values.push_back(h.axis_point[q] - h.ring.half);
        values.push_back(h.axis_point[q] + h.ring.half);
      } else {
        values.push_back(h.from);
        values.push_back(h.to);
      }
    }
    grid[static_cast<size_t>(q)] = merged(values, tolerance);
  }
  return grid;
}

// The grid and its knots, with the lookups every later stage uses.
struct BlockGrid {
  std::array<std::vector<double>, 3> planes;     // grid planes per axis
  std::array<std::vector<KnotVector>, 3> knots;  // per grid slab along each axis

  const std::vector<double>& along(int q) const { return planes[static_cast<size_t>(q)]; }
  double at(int q, int i) const { return planes[static_cast<size_t>(q)][static_cast<size_t>(i)]; }
  const KnotVector& slab_knots(int q, int i) const {
    return knots[static_cast<size_t>(q)][static_cast<size_t>(i)];
  }
};

// Each hole in its grid cells (its square one cell across, its length whole slabs), its loop cut
// into quarters on the square.
void place_holes(const BlockGrid& grid, double tolerance, std::vector<Hole>& holes) {
  for (Hole& h : holes) {
    Ring& ring = h.ring;
    place_ring(ring, grid.along(h.b), grid.along(h.c), tolerance, h.name, "plane");
    h.slab0 = grid_index(grid.along(h.axis), h.from, tolerance);
    h.slab1 = grid_index(grid.along(h.axis), h.to, tolerance);
    const Square square = grid_square(ring, grid.along(h.b), grid.along(h.c));
    cut_quarters(ring, square.x0, square.x1, square.y0, square.y1, h.name);
  }
}

// One degree everywhere; per grid slab the union of the knots of the quarters along it.
std::array<std::vector<KnotVector>, 3> grid_knots(const BlockGrid& grid, std::vector<Hole>& holes) {
  const int degree = ring_degree(ring_pointers(holes));
  std::array<std::vector<KnotVector>, 3> knots;
  for (int q = 0; q < 3; ++q)
    for (size_t i = 0; i + 1 < grid.along(q).size(); ++i) {
      std::vector<Patch*> quarters;
      for (Hole& h : holes)
        add_quarters_along(h.ring, h.b == q, h.c == q, static_cast<int>(i), quarters);
      knots[static_cast<size_t>(q)].push_back(common_knots(quarters, degree));
    }
  return knots;
}

// Each hole's four ring patches in its cross plane; refuses a hole whose ring cells are not solid
// (a point between the loop and the square's corner, in every slab along the hole).
void ring_cells(const BlockRegion& region, const BlockGrid& grid, std::vector<Hole>& holes) {
  for (Hole& h : holes) {
    const Ring& r = h.ring;
    const Square square = grid_square(r, grid.along(h.b), grid.along(h.c));
    h.cross_patches = square_ring_patches(r, square, grid.slab_knots(h.b, r.col),
                                          grid.slab_knots(h.c, r.row), h.name);
    for (int s = h.slab0; s < h.slab1; ++s) {
      Vector3d corner;
      corner[h.b] = square.x0 + 0.02 * (square.x1 - square.x0);
      corner[h.c] = square.y0 + 0.02 * (square.y1 - square.y0);
      corner[h.axis] = (grid.at(h.axis, s) + grid.at(h.axis, s + 1)) / 2.0;
      if (!region.inside(corner))
        refuse(h.name + " does not run through solid material over its length");
    }
  }
}

// The patches cell by cell (axis 0 fastest): a hole's four swept ring patches in its slabs, or a
// box where the cell is inside the solid.
std::vector<Patch> grid_patches(const BlockRegion& region, const BlockGrid& grid,
                                const std::vector<Hole>& holes) {
  std::vector<Patch> patches;
  const int n0 = static_cast<int>(grid.planes[0].size()) - 1,
            n1 = static_cast<int>(grid.planes[1].size()) - 1,
            n2 = static_cast<int>(grid.planes[2].size()) - 1;
  for (int k = 0; k < n2; ++k)
    for (int j = 0; j < n1; ++j)
      for (int i = 0; i < n0; ++i) {
        const std::array<int, 3> cell{i, j, k};
        const auto hole = std::find_if(holes.begin(), holes.end(), [&](const Hole& h) {
          const int s = cell[static_cast<size_t>(h.axis)];
          return cell[static_cast<size_t>(h.b)] == h.ring.col &&
                 cell[static_cast<size_t>(h.c)] == h.ring.row && s >= h.slab0 && s < h.slab1;
        });
        if (hole != holes.end()) {
          const int s = cell[static_cast<size_t>(hole->axis)];
          for (const Patch& cross : hole->cross_patches)
            patches.push_back(sweep(cross, *hole, grid.at(hole->axis, s),
                                    grid.at(hole->axis, s + 1), grid.slab_knots(hole->axis, s)));
          continue;
        }
        const Vector3d lo(grid.at(0, i), grid.at(1, j), grid.at(2, k)),
            hi(grid.at(0, i + 1), grid.at(1, j + 1), grid.at(2, k + 1));
        if (!region.inside((lo + hi) / 2.0)) continue;
        patches.push_back(
            box(lo, hi, {grid.slab_knots(0, i), grid.slab_knots(1, j), grid.slab_knots(2, k)}));
      }
  return patches;
}

}  // namespace

// The stages in order: the holes, their squares, the grid, the holes in their cells, the knots,
// the ring patches, the patches cell by cell.
std::vector<Patch> split_block_region(const BlockRegion& region, double tolerance) {
  if (!region.inside) refuse("the region has no inside test");
  for (int q = 0; q < 3; ++q)
    if (region.planes[static_cast<size_t>(q)].size() < 2)
      refuse("the solid has fewer than two faces normal to axis " + std::to_string(q));
  std::vector<Hole> holes = block_holes(region, tolerance);
  size_squares(region, tolerance, holes);
  BlockGrid grid;
  grid.planes = grid_planes(region, holes, tolerance);
  place_holes(grid, tolerance, holes);
  grid.knots = grid_knots(grid, holes);
  ring_cells(region, grid, holes);
  return grid_patches(region, grid, holes);
}

}  // namespace isospring::geometry
