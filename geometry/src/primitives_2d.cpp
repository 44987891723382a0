// Planar (z = 0) exact primitives.
#include <cmath>

#include "isospring/geometry/construction.hpp"
#include "isospring/geometry/primitives.hpp"
#include "isospring/nurbs/refine.hpp"
#include "parameter_checks.hpp"
#include "single_span_knots.hpp"

namespace isospring::geometry {

using detail::kCos45;
using detail::kLinear;
using detail::kQuadratic;

using detail::require_less;
using detail::require_positive;
using detail::require_sweep;
using nurbs::Patch;

Patches rectangle(double lx, double ly) {
  require_positive(lx, "rectangle", "size[0]");
  require_positive(ly, "rectangle", "size[1]");
  return {Patch({kLinear, kLinear}, {{0, 0, 0}, {lx, 0, 0}, {0, ly, 0}, {lx, ly, 0}})};
}

Patches disk(double radius) {
  require_positive(radius, "disk", "radius");
  // Corners at (+-s, +-s) on the circle; the middle points of the sides are the tangent
  // intersections at distance r sqrt 2 = 2 s. Weights are the tensor product of the quarter-arc
  // weights (1, cos 45, 1), so the centre point has weight 1/2.
  const double s = radius * kCos45;
  const std::vector<Eigen::Vector3d> points{{-s, -s, 0},    {0, -2 * s, 0}, {s, -s, 0},
                                            {-2 * s, 0, 0}, {0, 0, 0},      {2 * s, 0, 0},
                                            {-s, s, 0},     {0, 2 * s, 0},  {s, s, 0}};
  const double c = kCos45;
  const std::vector<double> weights{1, c, 1, c, c * c, c, 1, c, 1};
  return {Patch({kQuadratic, kQuadratic}, points, weights)};
}

Patches disk_five_patch(double radius, double inner_fraction) {
  require_positive(radius, "disk_five_patch", "radius");
  require_positive(inner_fraction, "disk_five_patch", "inner_fraction");
  require_less(inner_fraction, 1.0, "disk_five_patch", "inner_fraction", "1");
  const double h = inner_fraction * radius * kCos45;
  const double w[3] = {1.0, kCos45, 1.0};
  std::vector<Eigen::Vector3d> points;
  std::vector<double> weights;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      points.emplace_back((i - 1) * h, (j - 1) * h, 0.0);
      weights.push_back(w[i] * w[j]);
    }
  Patches patches{Patch({kQuadratic, kQuadratic}, points, weights)};
  for (int side = 0; side < 4; ++side) {
    const double phi = side * M_PI / 2;  // direction the outer patch faces
    const Eigen::Matrix3d rotation = (Eigen::Matrix3d() << std::cos(phi), -std::sin(phi), 0,
                                      std::sin(phi), std::cos(phi), 0, 0, 0, 1)
                                         .finished();
    // Inner side: the square's edge x = h with the same rational parametrisation as its arc.
    const Patch inner({kQuadratic},
                      {rotation * Eigen::Vector3d(h, -h, 0), rotation * Eigen::Vector3d(h, 0, 0),
                       rotation * Eigen::Vector3d(h, h, 0)},
                      {1.0, kCos45, 1.0});
    const Patch arc = circular_arc(Eigen::Vector3d::Zero(), radius, phi - M_PI / 4, M_PI / 2);
    patches.push_back(reverse_direction(ruled(inner, arc), 0));
  }
  return patches;
}

Patches ellipse(double a, double b) {
  require_positive(a, "ellipse", "radii[0]");
  require_positive(b, "ellipse", "radii[1]");
  return {transformed(disk(1.0)[0], Eigen::Vector3d(a, b, 1.0).asDiagonal())};
}

Patches annulus(double ri, double ro, double start, double sweep) {
  require_positive(ri, "annulus", "inner_radius");
  require_positive(ro, "annulus", "outer_radius");
  require_less(ri, ro, "annulus", "inner_radius", "outer_radius");
  require_sweep(sweep, 2 * M_PI, "annulus", "sweep");
  const Patch inner = circular_arc(Eigen::Vector3d::Zero(), ri, start, sweep);
  const Patch outer = circular_arc(Eigen::Vector3d::Zero(), ro, start, sweep);
  // ruled() appends the radial direction last; the benchmark convention has it first.
  return {swap_directions(ruled(inner, outer), 0, 1)};
}

Patches plate_with_hole_quarter(double hole_radius, double half_width) {
  require_positive(hole_radius, "plate_with_hole", "hole_radius");
  require_positive(half_width, "plate_with_hole", "half_width");
  require_less(hole_radius, half_width, "plate_with_hole", "hole_radius", "half_width");
  const double R = hole_radius, L = half_width;
  // Hole row: the quarter arc from 180 to 90 degrees with the knot 0.5 inserted, which yields the
  // tabulated (-1, tan 22.5), weight (1 + 1/sqrt 2)/2 points exactly.
  const Patch hole =
      nurbs::insert_knot(circular_arc(Eigen::Vector3d::Zero(), R, M_PI, -M_PI / 2), 0, 0.5);
  const double m = (R + L) / 2;     // middle row: 2.5 for R = 1, L = 4
  const double c = 0.15 * (R + L);  // middle row offsets: 0.75 for R = 1, L = 4
  std::vector<Eigen::Vector3d> points = hole.control_points();
  std::vector<double> weights = hole.weights();
  const std::vector<Eigen::Vector3d> middle{{-m, 0, 0}, {-m, c, 0}, {-c, m, 0}, {0, m, 0}};
  const std::vector<Eigen::Vector3d> outer{{-L, 0, 0}, {-L, L, 0}, {-L, L, 0}, {0, L, 0}};
  points.insert(points.end(), middle.begin(), middle.end());
  points.insert(points.end(), outer.begin(), outer.end());
  weights.resize(12, 1.0);
  return {Patch({hole.knots(0), kQuadratic}, points, weights)};
}

Patches plate_with_hole_quarter_two_patch(double hole_radius, double half_width) {
  const Patch whole = plate_with_hole_quarter(hole_radius, half_width)[0];
  auto [first, second] = split_patch(whole, 0, 0.5);
  return {first, second};
}

}  // namespace isospring::geometry
