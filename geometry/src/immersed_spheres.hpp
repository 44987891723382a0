#pragma once
// Boxes intersected with spheres (immersed_implicit_spheres.cpp).
#include <Eigen/Core>
#include <string>
#include <vector>

#include "isospring/geometry/immersed_domain.hpp"
#include "isospring/geometry/immersed_implicit.hpp"

namespace isospring::geometry::detail {

struct SphereRule {
  std::vector<Eigen::Vector3d> points;
  std::vector<double> weights;
  std::vector<BoundaryPoint> surface;  // sphere k is face first_face + k
};

/// Quadrature of the box [lo, hi] on the part side of every sphere (`points` Gauss points per
/// direction where no sphere crosses, `cut_points` along and across the lines of cut boxes,
/// bisected at most `depth` times), and the spheres' surface points in it. Returns whether a
/// sphere crosses the box.
bool sphere_cell_rule(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                      const std::vector<ImplicitSphere>& spheres, int first_face, int points,
                      int cut_points, int depth, std::string& warning, SphereRule& out);

/// The plane x_d = t over the rectangle [lo, hi] of the other two axes ((d+1)%3, (d+2)%3) on
/// the part side of every sphere.
void sphere_box_face(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, int d, double t,
                     const std::vector<ImplicitSphere>& spheres, int points, std::string& warning,
                     std::vector<Eigen::Vector3d>& out_points, std::vector<double>& out_weights);

}  // namespace isospring::geometry::detail
