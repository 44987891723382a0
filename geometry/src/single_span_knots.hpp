#pragma once
// Knot vectors of one Bezier span and the quarter-arc weight, shared by the hand-built primitives.
#include <cmath>

#include "isospring/nurbs/knot_vector.hpp"

namespace isospring::geometry::detail {

inline const nurbs::KnotVector kLinear(1, {0.0, 0.0, 1.0, 1.0});
inline const nurbs::KnotVector kQuadratic(2, {0.0, 0.0, 0.0, 1.0, 1.0, 1.0});
/// The middle weight of a rational quadratic quarter circle.
inline const double kCos45 = std::sqrt(0.5);

}  // namespace isospring::geometry::detail
