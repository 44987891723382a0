#pragma once
// Exact NURBS constructions that the primitives and the CAD import share: circular arcs,
// extrusion, revolution, ruled (linear) blends, splitting, reversing and affine maps. Every
// operation works on homogeneous control points, so rational geometry stays exact.
#include <Eigen/Core>
#include <vector>

#include "isospring/nurbs/patch.hpp"

namespace isospring::geometry {

/// Circular arc in the xy plane around `center`, radius r, from angle `start` sweeping `sweep`
/// radians (positive = counter-clockwise, |sweep| <= 2 pi). Degree 2, split into the fewest
/// segments of at most 90 degrees each (double interior knots, C0 in parameter, G1 in space);
/// the knots run from 0 to 1 with the segment breaks at equal spacing.
nurbs::Patch circular_arc(const Eigen::Vector3d& center, double radius, double start, double sweep);

/// A patch with one more parametric direction (appended last) running linearly (degree 1) from
/// `from` to `to`: control points and weights of the two must have the same knots in every
/// direction. Used for ruled surfaces, thick plates and radial directions.
nurbs::Patch ruled(const nurbs::Patch& from, const nurbs::Patch& to);

/// `profile` swept along `offset` (a new last direction of degree 1).
nurbs::Patch extrude(const nurbs::Patch& profile, const Eigen::Vector3d& offset);

/// `profile` (curve or surface) revolved about the z axis by `sweep` radians starting at its own
/// position; the revolution becomes the FIRST parametric direction (degree 2, arcs <= 90 deg).
/// Exact (The NURBS Book, A8.1). Points on the axis give collapsed control points.
nurbs::Patch revolve_about_z(const nurbs::Patch& profile, double sweep);

/// The same patch with parametric directions a and b exchanged (control net transposed).
nurbs::Patch swap_directions(const nurbs::Patch& patch, int a, int b);

/// The same patch with direction `dir` reversed (u -> a + b - u).
nurbs::Patch reverse_direction(const nurbs::Patch& patch, int dir);

/// Same geometry split at parameter `u` of direction `dir` into two patches (knots inserted to
/// multiplicity degree). u must be strictly inside the parameter range.
std::pair<nurbs::Patch, nurbs::Patch> split_patch(const nurbs::Patch& patch, int dir, double u);

/// Affine map x -> A x + b applied to the control points (exact for NURBS).
nurbs::Patch transformed(const nurbs::Patch& patch, const Eigen::Matrix3d& A,
                         const Eigen::Vector3d& b = Eigen::Vector3d::Zero());

/// Signed Jacobian determinant: det(dX/du, dX/dv, dX/dw) for volumes; for surfaces the z
/// component of dX/du x dX/dv when the patch is planar in xy (physical_dim 2), otherwise the
/// norm of the cross product (always >= 0); |dX/du| for curves.
double jacobian_determinant(const nurbs::Patch& patch, const nurbs::Param& u);

/// Smallest and largest Jacobian determinant over a grid of `samples` points per element and
/// direction (interior Gauss-like points, so collapsed edges/corners where det = 0 are skipped).
struct JacobianRange {
  double min = 0.0;
  double max = 0.0;
};
JacobianRange jacobian_range(const nurbs::Patch& patch, int samples = 4);

/// Reverses the first direction when the Jacobian is negative everywhere, so the result is
/// right-handed. Throws std::runtime_error when the sign changes inside the patch (folded map).
nurbs::Patch with_positive_jacobian(const nurbs::Patch& patch);

}  // namespace isospring::geometry
