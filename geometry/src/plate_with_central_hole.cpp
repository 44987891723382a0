#include "isospring/geometry/plate_with_central_hole.hpp"

#include <cmath>

#include "parameter_checks.hpp"
#include "single_span_knots.hpp"

namespace isospring::geometry {

using detail::kCos45;
using detail::kLinear;
using detail::kQuadratic;

using nurbs::Patch;

namespace {

Eigen::Vector3d polar(double radius, double angle) {
  return {radius * std::cos(angle), radius * std::sin(angle), 0.0};
}

// The ring patch between the hole arc [centre_angle + 45, centre_angle - 45] degrees (clockwise)
// and the facing side of the square of half-width h. Both rows carry the quarter-arc weights
// (1, cos 45, 1): on the arc that makes it exact, on the straight side it only reparametrises,
// and it is what the rectangles copy to conform.
Patch ring_patch(const Eigen::Vector3d& centre, double radius, double h, double centre_angle) {
  const double a = centre_angle, q = M_PI / 4;
  const std::vector<Eigen::Vector3d> points{
      centre + polar(radius, a + q), centre + polar(radius / kCos45, a),
      centre + polar(radius, a - q), centre + polar(h / kCos45, a + q),
      centre + polar(h, a),          centre + polar(h / kCos45, a - q)};
  const std::vector<double> weights{1, kCos45, 1, 1, kCos45, 1};
  return Patch({kQuadratic, kLinear}, points, weights);
}

// The rectangle from the square side x = x_side (y from y_first to y_last, the ring patch's u
// direction) out to x = x_end.
Patch end_rectangle(double x_side, double x_end, double y_first, double y_last) {
  const double ym = (y_first + y_last) / 2;
  const std::vector<Eigen::Vector3d> points{{x_side, y_first, 0}, {x_side, ym, 0},
                                            {x_side, y_last, 0},  {x_end, y_first, 0},
                                            {x_end, ym, 0},       {x_end, y_last, 0}};
  const std::vector<double> weights{1, kCos45, 1, 1, kCos45, 1};
  return Patch({kQuadratic, kLinear}, points, weights);
}

}  // namespace

Patches plate_with_central_hole(double length, double width, double hole_radius) {
  detail::require_positive(length, "plate_with_central_hole", "length");
  detail::require_positive(width, "plate_with_central_hole", "width");
  detail::require_positive(hole_radius, "plate_with_central_hole", "hole_radius");
  detail::require_less(hole_radius, width / 2, "plate_with_central_hole", "hole_radius",
                       "width / 2");
  if (length < width)
    throw nurbs::InputError("plate_with_central_hole: length (" + std::to_string(length) +
                            ") must be at least width (" + std::to_string(width) +
                            "); the hole sits in a square of side width");
  const double h = width / 2;
  const Eigen::Vector3d centre(length / 2, h, 0.0);
  Patches ring;
  for (const double degrees : {180.0, 90.0, 0.0, 270.0})
    ring.push_back(ring_patch(centre, hole_radius, h, degrees * M_PI / 180));
  if (length == width) return ring;
  Patches patches;
  patches.push_back(end_rectangle(centre.x() - h, 0.0, 0.0, width));  // u along +y, like ring 0
  patches.insert(patches.end(), ring.begin(), ring.end());
  patches.push_back(end_rectangle(centre.x() + h, length, width, 0.0));  // u along -y
  return patches;
}

}  // namespace isospring::geometry
