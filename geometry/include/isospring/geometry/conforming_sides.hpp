#pragma once
// Neighbouring CAD faces are cut into patches independently (planar split, Coons), so a straight
// edge they share can carry different knots or degrees on its two sides; the multipatch analysis
// would then not glue them. This pass makes such sides conforming without changing the geometry.
#include <vector>

#include "isospring/nurbs/patch.hpp"

namespace isospring::geometry {

/// For every two sides of different surface patches (param_dim 2) that are the same straight
/// segment (end points within `tolerance`, every control point on the chord), both patches are
/// degree-elevated along the side to the larger degree and given the union of the side's knots
/// (by multiplicity, in the side's normalised parameter): exact refinement, the geometry is
/// unchanged. Refining a patch along a direction changes its opposite side too, so the pass
/// repeats until no shared straight side differs (at most as many rounds as patches). Sides
/// that are straight but parametrised differently (not linearly in their knots) still end up
/// with different control points; the analysis names them (DofMap::unglued_interfaces).
std::vector<nurbs::Patch> conform_shared_sides(std::vector<nurbs::Patch> patches, double tolerance);

}  // namespace isospring::geometry
