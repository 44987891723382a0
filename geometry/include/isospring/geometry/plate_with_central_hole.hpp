#pragma once
// A rectangular plate with a central circular hole (the tensile specimen of DIC experiments) as
// 6 conforming, singularity-free patches.
#include "isospring/geometry/primitives.hpp"

namespace isospring::geometry {

/// The plate [0, length] x [0, width] (z = 0) with a hole of radius `hole_radius` centred at
/// (length / 2, width / 2). The square of side `width` around the hole is 4 ring patches (each
/// from a 90-degree arc of the hole to one side of the square, rational quadratic along the arc,
/// linear outward); the rest are 2 rectangles with the same rational parametrisation along y, so
/// every interface conforms (identical knots, weights and control points). In every patch u runs
/// clockwise around the hole and v away from it (right-handed). Patch order: 0 left rectangle,
/// 1-4 ring patches centred at 180, 90, 0, 270 degrees, 5 right rectangle. The loaded ends are
/// side v1 of patch 0 (x = 0) and of patch 5 (x = length). When length == width there are no
/// rectangles (4 patches; ends: v1 of ring patches 0 and 2). Requires 0 < hole_radius < width / 2
/// and length >= width.
Patches plate_with_central_hole(double length, double width, double hole_radius);

}  // namespace isospring::geometry
