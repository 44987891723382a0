#pragma once
// The discretisation ladder of a case file for identify's discretisation check
// (fitting/discretization_check.hpp): k-refinement from the case's exact geometry, so every level
// is geometry-exact, keeps the parametrisation and has maximal continuity.
//
// Level l raises the degree of every parametric direction by l, up to degree 3 for solids and 4
// for plane problems (a direction already above keeps its degree); once no direction can be
// raised, each further level doubles the elements of every direction. Degree elevation first:
// for the same DOFs it removes far more of the error of smooth fields than splitting does, and
// the next levels' splitting catches what elevation alone misses on very coarse nets (one
// element through a thickness).
//
// A single-patch solid with a clamped side gets graded nets instead (graded_ladder.hpp): the same
// degrees and element counts, the spans crowded towards the clamp and its edges, where the
// singular stresses are; its descriptions end in ", graded towards the clamp (u0)".
#include "isospring/fitting/discretization_check.hpp"
#include "isospring/io/case_file.hpp"

namespace isospring::io {

/// Level l >= 1 as described above; level 0 is problem_at(c, c.discretization).
CaseDiscretization ladder_discretization(const Case& c, int level);

/// The ladder as identify takes it; its descriptions read "degree 3, 20 x 4 x 4 elements"
/// (graded: "..., graded towards the clamp (u0)").
fitting::DiscretizationLadder case_refinement_ladder(const Case& c);

/// The first level of the ladder's one family for the check's convergence ratios
/// (fitting::DiscretizationOptions::ratio_from_level): on graded nets the first graded level
/// with the final degrees (the case's own level 0 is uniform); 0 on uniform nets, whose ratios
/// may come from every level.
int case_ladder_ratio_from_level(const Case& c);

/// Between levels l - 1 and l when both have the same degrees (l doubles the elements): the
/// elements of level l - 1 times 1.5, rounded up (10 x 2 x 2 -> 15 x 3 x 3, between 10 x 2 x 2
/// and 20 x 4 x 4), each rounded up to a multiple of the exact geometry's spans in its direction.
/// nullopt when level l raises a degree.
std::optional<CaseDiscretization> intermediate_discretization(const Case& c, int level);

/// intermediate_discretization as identify's DiscretizationOptions::intermediate takes it.
fitting::DiscretizationLadder case_refinement_intermediate(const Case& c);

}  // namespace isospring::io
