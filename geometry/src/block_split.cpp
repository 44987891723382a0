// An orthogonal solid with through-holes -> conforming hexahedral patches (see block_split.hpp).
#include "isospring/geometry/block_split.hpp"

#include <algorithm>
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

}  // namespace

std::vector<Patch> split_block_region(const BlockRegion& region, double tolerance) {
  if (!region.inside) refuse("the region has no inside test");
  for (int q = 0; q < 3; ++q)
    if (region.planes[static_cast<size_t>(q)].size() < 2)
      refuse("the solid has fewer than two faces normal to axis " + std::to_string(q));
  std::vector<Hole> holes;
  for (size_t h = 0; h < region.holes.size(); ++h) {
    const ThroughHole& in = region.holes[h];
    Hole hole;
    hole.name = "hole " + std::to_string(h + 1);
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
  auto crosses = [](const Hole& h, int q) { return h.b == q || h.c == q; };
  // Half sides of the squares: no face plane inside a square (the grid planes run through the
  // whole solid); two holes apart by d along a common cross axis share d in proportion to their
  // sizes; holes on one line (same coordinate on a common cross axis) get the same square.
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
  for (size_t pass = 0; pass < holes.size(); ++pass)
    for (Hole& h : holes)
      for (Hole& k : holes)
        for (int q = 0; q < 3; ++q)
          if (&k != &h && crosses(h, q) && crosses(k, q) &&
              std::abs(k.axis_point[q] - h.axis_point[q]) <= tolerance)
            h.ring.half = k.ring.half = std::min(h.ring.half, k.ring.half);
  for (const Hole& h : holes)
    if (h.ring.extent > 0.9 * h.ring.half) {
      std::ostringstream why;
      why.precision(3);
      why << h.name << " (half size " << h.ring.extent << ") is too close to a face or to "
          << "another hole for a ring of patches (room: a square of half side " << h.ring.half
          << ")";
      refuse(why.str());
    }
  // The grid: face planes, the squares' sides and the holes' ends.
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
  auto at = [&](int q, int i) { return grid[static_cast<size_t>(q)][static_cast<size_t>(i)]; };
  auto index = [&](int q, double v) {
    return grid_index(grid[static_cast<size_t>(q)], v, tolerance);
  };
  for (Hole& h : holes) {
    Ring& ring = h.ring;
    ring.col = index(h.b, h.axis_point[h.b] - ring.half);
    ring.row = index(h.c, h.axis_point[h.c] - ring.half);
    if (ring.col + 1 != index(h.b, h.axis_point[h.b] + ring.half) ||
        ring.row + 1 != index(h.c, h.axis_point[h.c] + ring.half))
      refuse("a cut plane crosses the square around " + h.name);
    h.slab0 = index(h.axis, h.from);
    h.slab1 = index(h.axis, h.to);
    cut_quarters(ring, at(h.b, ring.col), at(h.b, ring.col + 1), at(h.c, ring.row),
                 at(h.c, ring.row + 1), h.name);
  }
  // One degree everywhere; per grid slab the union of the knots of the quarters along it.
  int degree = 2;
  for (const Hole& h : holes)
    for (const Patch* q : {&h.ring.below, &h.ring.right, &h.ring.above, &h.ring.left})
      degree = std::max(degree, q->degree(0));
  std::array<std::vector<KnotVector>, 3> knots;
  for (int q = 0; q < 3; ++q)
    for (size_t i = 0; i + 1 < grid[static_cast<size_t>(q)].size(); ++i) {
      std::vector<Patch*> quarters;
      for (Hole& h : holes) {
        if (h.b == q && h.ring.col == static_cast<int>(i)) {
          quarters.push_back(&h.ring.below);
          quarters.push_back(&h.ring.above);
        }
        if (h.c == q && h.ring.row == static_cast<int>(i)) {
          quarters.push_back(&h.ring.left);
          quarters.push_back(&h.ring.right);
        }
      }
      knots[static_cast<size_t>(q)].push_back(common_knots(quarters, degree));
    }
  auto slab_knots = [&](int q, int i) -> const KnotVector& {
    return knots[static_cast<size_t>(q)][static_cast<size_t>(i)];
  };
  for (Hole& h : holes) {
    const Ring& r = h.ring;
    const double x0 = at(h.b, r.col), x1 = at(h.b, r.col + 1), y0 = at(h.c, r.row),
                 y1 = at(h.c, r.row + 1);
    const Vector3d bl(x0, y0, 0), br(x1, y0, 0), tl(x0, y1, 0), tr(x1, y1, 0);
    const KnotVector &along_x = slab_knots(h.b, r.col), &along_y = slab_knots(h.c, r.row);
    h.cross_patches = {ring_patch(r.below, line(bl, br, along_x), true, h.name),
                       ring_patch(r.right, line(br, tr, along_y), true, h.name),
                       ring_patch(r.above, line(tl, tr, along_x), true, h.name),
                       ring_patch(r.left, line(bl, tl, along_y), true, h.name)};
    // The ring's cells must be solid: a point between the loop and the square's corner.
    for (int s = h.slab0; s < h.slab1; ++s) {
      Vector3d corner;
      corner[h.b] = x0 + 0.02 * (x1 - x0);
      corner[h.c] = y0 + 0.02 * (y1 - y0);
      corner[h.axis] = (at(h.axis, s) + at(h.axis, s + 1)) / 2.0;
      if (!region.inside(corner))
        refuse(h.name + " does not run through solid material over its length");
    }
  }
  std::vector<Patch> patches;
  const int n0 = static_cast<int>(grid[0].size()) - 1, n1 = static_cast<int>(grid[1].size()) - 1,
            n2 = static_cast<int>(grid[2].size()) - 1;
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
            patches.push_back(sweep(cross, *hole, at(hole->axis, s), at(hole->axis, s + 1),
                                    slab_knots(hole->axis, s)));
          continue;
        }
        const Vector3d lo(at(0, i), at(1, j), at(2, k)),
            hi(at(0, i + 1), at(1, j + 1), at(2, k + 1));
        if (!region.inside((lo + hi) / 2.0)) continue;
        patches.push_back(box(lo, hi, {slab_knots(0, i), slab_knots(1, j), slab_knots(2, k)}));
      }
  return patches;
}

}  // namespace isospring::geometry
