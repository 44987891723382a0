#pragma once
// Graded knots of an immersed background grid along one axis (immersed_cad.hpp, GradingPlane).
#include <vector>

#include "isospring/geometry/immersed_cad.hpp"

namespace isospring::geometry::detail {

/// The cell boundaries of [a, b] along `axis` (a first, b last, increasing): `base_cells` equal
/// cells when no plane grades this axis; otherwise cells that follow the length
/// s(x) = min(H, min over planes (smallest + (ratio - 1) |x - at|)), H = (b - a) / base_cells,
/// which is a geometric progression by `ratio` away from each plane. The cells are placed by
/// equidistributing 1 / s (each cell holds an equal share of its integral, the share at most 1),
/// so none is longer than s asks for and their number is the integral rounded up.
std::vector<double> graded_ticks(double a, double b, int base_cells,
                                 const std::vector<GradingPlane>& planes, int axis);

}  // namespace isospring::geometry::detail
