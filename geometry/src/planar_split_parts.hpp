#pragma once
// The pieces of the planar split (planar_split.cpp) that the block split of solids
// (block_split.cpp) builds on: a hole's loop, its square and the four ruled ring patches between
// them, and the knots shared along a grid column or row (defined in planar_split_parts.cpp).
#include <Eigen/Core>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "isospring/nurbs/patch.hpp"

namespace isospring::geometry::planar_split_detail {

using Loop = std::vector<nurbs::Patch>;

/// Throws std::invalid_argument(why): the region cannot be cut this way.
[[noreturn]] void refuse(const std::string& why);

/// A hole (or, for a disk, the outline) with the square of grid cell (col, row) around it; all
/// in the plane z = 0.
struct Ring {
  Loop loop;
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  double extent = 0.0;  // largest |x - cx| or |y - cy| on the loop
  double half = std::numeric_limits<double>::infinity();  // half side of its square
  int col = -1, row = -1;
  bool hole = true;  // the loop inside the square (hole) or outside (outline of a disk)
  nurbs::Patch below, right, above, left;  // quarters of the loop, along +x (below, above) or +y
};

/// The loop running counter-clockwise (the ring construction relies on it).
Loop counter_clockwise(const Loop& loop);
/// Area of the region a closed loop encloses (Green's theorem on the exact curves, Gauss
/// quadrature on every knot span: round-off for circles).
double enclosed_area(const Loop& loop);
/// Sets the ring's centre (the centroid of the area its loop encloses) and extent.
void prepare_ring(Ring& ring);
/// Coordinates within `tolerance` merged (sorted, first of each cluster kept).
std::vector<double> merged(std::vector<double> values, double tolerance);
/// Index of `v` in the grid (within `tolerance`), or -1.
int grid_index(const std::vector<double>& grid, double v, double tolerance);
/// Cuts the ring's loop on the rays from its centre through the corners of [x0, x1] x [y0, y1].
void cut_quarters(Ring& ring, double x0, double x1, double y0, double y1, const std::string& what);
/// [0, 0, ..., 1, 1]: one span of the given degree.
nurbs::KnotVector plain_knots(int degree);
/// Makes the quarters running along one grid column (row) compatible with each other and with
/// a straight line of `degree` (same degree, union of knots over [0, 1]); returns those knots.
nurbs::KnotVector common_knots(const std::vector<nurbs::Patch*>& quarters, int degree);
/// a + g (b - a), exactly b at g = 1: shared sides get bitwise equal control points.
double lerp(double a, double b, double g);
/// The segment a -> b with the given knots, parametrised linearly (control points at the
/// Greville abscissae), weights 1.
nurbs::Patch line(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                  const nurbs::KnotVector& knots);
/// The ruled patch between a quarter of the loop and a side of its square, right-handed in the
/// plane; refuses (naming `what`) when it folds.
nurbs::Patch ring_patch(const nurbs::Patch& quarter, const nurbs::Patch& side, bool hole,
                        const std::string& what);

/// The curve's point at its first (last) parameter.
Eigen::Vector3d start_point(const nurbs::Patch& c);
Eigen::Vector3d end_point(const nurbs::Patch& c);
/// A curve that is a straight segment: every control point on its chord (B-spline convex hull).
bool straight(const nurbs::Patch& c, double tolerance);
/// Whether x is inside the polygon (even-odd rule, in the plane z = 0).
bool inside_polygon(const std::vector<Eigen::Vector3d>& polygon, const Eigen::Vector3d& x);
/// "hole <h + 1>": holes are named from 1 in messages.
std::string hole_name(size_t h);
/// The rectangle [x0, x1] x [y0, y1] with the given knots along x and y (weights 1).
nurbs::Patch rectangle(double x0, double x1, double y0, double y1, const nurbs::KnotVector& ku,
                       const nurbs::KnotVector& kv);

// The stages both splits run on their rings (a ring's square lies in the plane of the grid axes
// that are its x and y), in this order.

/// Rings in line (in_line(h, k): on one grid line through both centres) get the same square,
/// the smaller one, or one's grid lines would cross the other's square.
void share_squares_in_line(const std::vector<Ring*>& rings,
                           const std::function<bool(size_t, size_t)>& in_line);
/// Refuses (naming the ring `name` and what else bounds its square, `bounds`) when the ring's
/// loop reaches beyond 0.9 of its square's half side: no room for a ring of patches.
void check_ring_room(const Ring& ring, const std::string& name, const std::string& bounds);
/// Sets the ring's grid cell (col in gx, row in gy); refuses ("a cut <cut> crosses the square
/// around <what>") when its square is not exactly one cell.
void place_ring(Ring& ring, const std::vector<double>& gx, const std::vector<double>& gy,
                double tolerance, const std::string& what, const std::string& cut);
/// The ring's square [x0, x1] x [y0, y1]: its grid cell's lines.
struct Square {
  double x0, x1, y0, y1;
};
Square grid_square(const Ring& ring, const std::vector<double>& gx, const std::vector<double>& gy);
/// One degree for every patch: at least 2 and that of every quarter of every ring.
int ring_degree(const std::vector<Ring*>& rings);
/// Adds the ring's quarters that run along grid slab i of one axis: below and above when the
/// axis is the ring's x (`x_axis`) and i its column, left and right when it is its y (`y_axis`)
/// and i its row.
void add_quarters_along(Ring& ring, bool x_axis, bool y_axis, int i,
                        std::vector<nurbs::Patch*>& quarters);
/// The four ring patches between the ring's quarters and the sides of its square (sides along x
/// with knots `along_x`, along y with `along_y`): below, right, above, left.
std::vector<nurbs::Patch> square_ring_patches(const Ring& ring, const Square& square,
                                              const nurbs::KnotVector& along_x,
                                              const nurbs::KnotVector& along_y,
                                              const std::string& what);

}  // namespace isospring::geometry::planar_split_detail
