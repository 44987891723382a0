#pragma once
// Quadrature of a rectangle intersected with the sides of circles, along lines intersected with
// the circles in closed form (see immersed_implicit.hpp for why this is accurate).
#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

namespace isospring::geometry::detail {

struct LineCircle {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double radius = 1.0;
  bool part_inside = false;
  bool breaks_only = false;  // no side: only splits the lines (a kink of the integrand there)
};

struct Rectangle {
  Eigen::Vector2d lo = Eigen::Vector2d::Zero();
  Eigen::Vector2d hi = Eigen::Vector2d::Zero();
};

struct PlaneRule {
  std::vector<Eigen::Vector2d> points;
  std::vector<double> weights;
};

enum class Overlap { kNone, kFull, kPartial };

/// Where the rectangle lies relative to the part side of one circle.
Overlap circle_overlap(const Rectangle& rect, const LineCircle& circle);

/// Is x on the part side of every circle (strictly, by more than `tolerance`)?
bool on_part_side(const Eigen::Vector2d& x, const std::vector<LineCircle>& circles,
                  double tolerance);

/// Quadrature of rect intersected with the part sides of `circles` (all of which cross the
/// rectangle): `points` Gauss points per line piece in both directions. A cell that cannot be
/// bisected to a line direction free of tangents within `max_depth` levels gets a note in
/// `warning` (the rule is then still used, with an algebraic instead of exponential convergence).
PlaneRule cut_rectangle_rule(const Rectangle& rect, const std::vector<LineCircle>& circles,
                             int points, std::string& warning, int max_depth = 8);

/// Intersections of two circles (0, 1 or 2 points).
std::vector<Eigen::Vector2d> circle_intersections(const LineCircle& a, const LineCircle& b);

}  // namespace isospring::geometry::detail

namespace isospring::geometry {
struct ImplicitShape;
struct ImmersedDomain;
namespace detail {
/// Boundary points of an implicit shape (immersed_implicit_boundary.cpp): every piece between grid
/// lines (`lines` per direction) gets `points` Gauss points; in 3D the z faces take the
/// cross-section's cell rules `cross_section`.
void add_implicit_boundary(const ImplicitShape& shape,
                           const std::array<std::vector<double>, 3>& lines, int points,
                           const std::vector<PlaneRule>& cross_section, ImmersedDomain& domain);
}  // namespace detail
}  // namespace isospring::geometry
