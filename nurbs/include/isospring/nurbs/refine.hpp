#pragma once
// Exact refinement in homogeneous coordinates: the geometry (and parametrisation) never changes.
#include <vector>

#include "isospring/nurbs/patch.hpp"

namespace isospring::nurbs {

/// Insert the knot u `times` times in direction dir (The NURBS Book A5.1, via knot refinement).
Patch insert_knot(const Patch& patch, int dir, double u, int times = 1);
/// Insert many knots at once in direction dir (The NURBS Book A5.4); `new_knots` need not be
/// sorted. Throws InputError if a knot lies outside the range or would exceed multiplicity p.
Patch refine_knots(const Patch& patch, int dir, std::vector<double> new_knots);
/// Split every non-empty span of direction dir into `splits` equal spans.
Patch refine_uniform(const Patch& patch, int dir, int splits);
/// Split every span of every direction into `splits`.
Patch refine_uniform(const Patch& patch, int splits);
/// Raise the degree of direction dir by `times` (The NURBS Book A5.9); interior continuity is kept.
Patch elevate_degree(const Patch& patch, int dir, int times);
/// Raise the degree of every direction by `times`.
Patch elevate_degree(const Patch& patch, int times);
/// k-refinement: elevate each direction to degree[dir] first, then split every span into
/// splits[dir] (new interior knots get multiplicity 1, so continuity is C^{p-1}).
Patch k_refine(const Patch& patch, const std::array<int, 3>& degree,
               const std::array<int, 3>& splits);

/// Knots that split each span of `knots` into `splits` equal parts (the knots to insert).
std::vector<double> uniform_split_knots(const KnotVector& knots, int splits);

}  // namespace isospring::nurbs
