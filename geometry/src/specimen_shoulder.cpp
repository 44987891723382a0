#include "isospring/geometry/specimen_shoulder.hpp"

#include <cmath>
#include <string>

#include "parameter_checks.hpp"
#include "single_span_knots.hpp"

namespace isospring::geometry {

using detail::kCos45;
using detail::kLinear;
using detail::kQuadratic;

using nurbs::Patch;

Patches add_specimen_shoulder(Patches test_section, double width,
                              const SpecimenShoulder& shoulder) {
  const char* name = "specimen shoulder";
  detail::require_positive(width, name, "width");
  detail::require_positive(shoulder.fillet_radius, name, "fillet_radius");
  if (!(std::isfinite(shoulder.straight_length) && shoulder.straight_length >= 0.0))
    throw nurbs::InputError(std::string(name) + ": straight_length must be zero or positive, got " +
                            std::to_string(shoulder.straight_length));
  detail::require_less(width, shoulder.shoulder_width, name, "width", "shoulder_width");
  const double rise = (shoulder.shoulder_width - width) / 2;  // per side
  if (rise > shoulder.fillet_radius * (1 + 1e-12))
    throw nurbs::InputError(std::string(name) + ": shoulder_width (" +
                            std::to_string(shoulder.shoulder_width) +
                            ") is beyond width + 2 fillet_radius (" +
                            std::to_string(width + 2 * shoulder.fillet_radius) +
                            "): a circular fillet tangent to the test section cannot reach it");
  if (test_section.empty()) throw nurbs::InputError(std::string(name) + ": no test section");

  const double ym = width / 2, x0 = -shoulder.straight_length;
  // plate_with_central_hole's weights along y (its ring patches' quarter arcs): copying them is
  // what makes the interfaces conform.
  const std::vector<double> row_weights{1, kCos45, 1};
  if (shoulder.straight_length > 0.0) {
    const std::vector<Eigen::Vector3d> points{{0, 0, 0},  {0, ym, 0},  {0, width, 0},
                                              {x0, 0, 0}, {x0, ym, 0}, {x0, width, 0}};
    std::vector<double> weights = row_weights;
    weights.insert(weights.end(), row_weights.begin(), row_weights.end());
    test_section.push_back(Patch({kQuadratic, kLinear}, points, weights));
  }

  // The upper fillet: a circle of radius R centred at (x0, width + R), from (x0, width) (where it
  // is tangent to the side) to the shoulder at height width + rise, over the angle theta with
  // sin theta = run / R. As a rational quadratic: end points, the tangents' intersection at
  // (x0 - R tan(theta / 2), width), middle weight cos(theta / 2). The lower fillet mirrors it,
  // and the middle row is the straight line between: a tensor product of the y rows' weights
  // (1, cos 45, 1) and the arc's (1, cos(theta / 2), 1).
  const double R = shoulder.fillet_radius;
  const double run = std::sqrt(rise * (2 * R - rise));  // sqrt(R^2 - (R - rise)^2)
  const double theta = std::asin(std::min(1.0, run / R));
  const double x1 = x0 - R * std::tan(theta / 2), x2 = x0 - run;
  const double arc_weight = std::cos(theta / 2);
  const std::vector<Eigen::Vector3d> points{{x0, 0, 0},     {x0, ym, 0}, {x0, width, 0},
                                            {x1, 0, 0},     {x1, ym, 0}, {x1, width, 0},
                                            {x2, -rise, 0}, {x2, ym, 0}, {x2, width + rise, 0}};
  std::vector<double> weights;
  for (const double wv : {1.0, arc_weight, 1.0})
    for (const double wu : row_weights) weights.push_back(wu * wv);
  test_section.push_back(Patch({kQuadratic, kQuadratic}, points, weights));
  return test_section;
}

}  // namespace isospring::geometry
