#pragma once
// The shoulder of a tensile specimen: the straight run past the measured section and the circular
// fillet that widens it towards the grip, as exact NURBS patches that conform to
// plate_with_central_hole's end at x = 0.
#include "isospring/geometry/primitives.hpp"

namespace isospring::geometry {

/// Where a dog-bone specimen widens beyond its test section (all lengths in the geometry's
/// units). From the test section's end at x = 0 the width stays for `straight_length`, then two
/// circular fillets of radius `fillet_radius` (tangent to the test section's sides) widen it
/// symmetrically to `shoulder_width`; the shoulder ends where the fillets do, at
/// x = -(straight_length + sqrt(R^2 - (R - e)^2)), e = (shoulder_width - width) / 2. This is the
/// "simplified dog-bone" of Anton et al. (2024) for the DIC plate with a hole: 5 mm straight,
/// R = 25 mm, widening from 20 to 30 mm, clamped at its left end.
struct SpecimenShoulder {
  double straight_length = 0.0;
  double fillet_radius = 0.0;
  double shoulder_width = 0.0;
};

/// Appends to `test_section` (plate_with_central_hole(length, width, ...), whose patch 0 ends at
/// x = 0 with y in [0, width]) two patches: the straight run (a rectangle with patch 0's rational
/// parametrisation along y, so the interface conforms) and the fillet patch (rational quadratic
/// along x as well: its top and bottom sides are the exact fillet arcs). Both keep patch 0's
/// orientation (u along +y, v along -x). The new left end is side v1 of the last patch.
/// `straight_length` may be 0 (then only the fillet patch is added). Requires
/// width < shoulder_width <= width + 2 fillet_radius.
Patches add_specimen_shoulder(Patches test_section, double width, const SpecimenShoulder& shoulder);

}  // namespace isospring::geometry
