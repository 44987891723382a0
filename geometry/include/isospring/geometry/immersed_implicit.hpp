#pragma once
// Immersed domains of analytic shapes, for verification against closed forms: an axis-aligned
// box intersected with discs and circular holes (2D), or the same cross-section extruded along z
// (3D: a box with cylindrical holes, a thick-walled cylinder sector).
//
// Cut cells are integrated along lines: in each cut cell the outer direction is chosen so that no
// circle has a tangent parallel to the lines inside the cell (the cell is bisected until such a
// direction exists), the outer interval is split where the lines' topology changes (circle
// crossings of the cell's edges, circle-circle intersections), and every line is intersected with
// the circles in closed form. Along a line the rule is Gauss exact for polynomials; across lines
// the integrand (a polynomial integrated between smooth analytic limits) is smooth on every piece,
// so the rule converges exponentially in the number of points. Boundary points lie on the exact
// arcs and straight sides, one Gauss rule per piece between grid lines.
//
// Spheres: in each cut cell the lines run along an axis d for which every sphere's silhouette
// (where lines along d touch it) stays at least half the cell's cross-section away from where
// the sphere crosses the cell (the cell is bisected until such an axis exists). The lines'
// limits are then smooth except where a line leaves through the cell's faces, on circles (the
// sphere cut by the face planes), which the rule across the lines (the 2D rule above, with those
// circles as break curves) follows exactly. Sphere points are the graph of the sphere over the
// same kind of 2D rule, weighted by r / |x_d - c_d|.
#include <Eigen/Core>
#include <limits>
#include <vector>

#include "isospring/geometry/immersed_domain.hpp"

namespace isospring::geometry {

/// A circle in the x-y plane (in 3D a cylinder along z); the part lies inside it
/// (`part_inside`) or outside it (a hole).
struct ImplicitCircle {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double radius = 1.0;
  bool part_inside = false;
};

/// A sphere (3D only); the part lies inside it or outside it (a spherical void).
struct ImplicitSphere {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double radius = 1.0;
  bool part_inside = true;
};

/// The part: {x in the box} intersected with every circle's (or sphere's) side.
/// Faces (BoundaryPoint::face, face_count = sides + circles):
///   2D: 0 x = box_min.x, 1 x = box_max.x, 2 y = box_min.y, 3 y = box_max.y, 4 + k circle k;
///   3D: 0..3 as in 2D, 4 z = box_min.z, 5 z = box_max.z, 6 + k cylinder k (or sphere k).
/// A 3D shape has cylinders or spheres, not both; spheres must not intersect each other.
/// A face the part does not touch (a box side outside a disc) keeps its number and has no points.
struct ImplicitShape {
  int dimension = 2;  // 2 or 3
  Eigen::Vector3d box_min = Eigen::Vector3d::Zero();
  Eigen::Vector3d box_max = Eigen::Vector3d::Ones();
  std::vector<ImplicitCircle> circles;
  std::vector<ImplicitSphere> spheres;
};

/// The background grid: a uniform B-spline box of `degree` with `elements` per direction over
/// [grid_min, grid_max] (empty grid_min/grid_max: the shape's box). The grid must contain the box.
struct ImplicitGrid {
  int degree = 2;
  Eigen::Vector3i elements = Eigen::Vector3i(8, 8, 8);
  Eigen::Vector3d grid_min = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  Eigen::Vector3d grid_max = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  int points = 0;      // Gauss points per direction in uncut cells (0: degree + 1)
  int cut_points = 0;  // Gauss points per line piece in cut cells and boundary pieces (0: 2 (p+1))
};

/// Throws nurbs::InputError (naming the field) for an empty box, a non-positive radius, a grid
/// that does not contain the box, a degree below 1 or fewer than 1 element, or a part that fills
/// no cell. ImmersedCell::span holds the knot-span index (as KnotVector::find_span returns it).
ImmersedDomain immerse_implicit(const ImplicitShape& shape, const ImplicitGrid& grid = {});

}  // namespace isospring::geometry
