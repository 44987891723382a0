#pragma once
// The pieces of the planar split (planar_split.cpp) that the block split of solids
// (block_split.cpp) builds on: a hole's loop, its square and the four ruled ring patches between
// them, and the knots shared along a grid column or row.
#include <Eigen/Core>
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

}  // namespace isospring::geometry::planar_split_detail
