#pragma once
// The ladder of background grids of an immersed case for identify's discretisation check
// (fitting/identify_immersed_check.hpp): level l has the case's cells per direction times
// 2^(l/2) (rounded; the cell size shrinks by sqrt 2 per level, halves every two), at the case's
// degree, in the same box (the markers keep their places).
//
// Why not the body-fitted ladder's degree elevation first (io/case_refinement_ladder.hpp), and
// why steps of sqrt 2 rather than halving: on the rounded bracket of
// examples/immersed/identify_bracket (10 x 5 x 5 quadratic cells, 1,260 DOFs), raising the
// degree to 3 moved the markers by 2.6e-9 m rms but the next level (20 x 10 x 10, cubic) by
// 9.2e-9 m more (a ratio of 2.6: elevation on cells a fifth of the part's size is
// pre-asymptotic), and the cubic immersed assembly costs about 3 x the quadratic one per DOF
// (24 s against 7.6 s of wall time on the shared machine, for 7,059 and 5,256 DOFs). Halving the
// cells multiplies the DOFs of a solid by about 5.6 (40 x 20 x 20 quadratic cells: 29,298 DOFs,
// over the default budget), so a halving ladder from the default grid would stop after one step
// with no convergence ratio; steps of sqrt 2 (x ~2.5 DOFs) give three levels within the budget and
// a ratio.
//
// Every level is immersed again on the exact B-rep (its time is in the level's description).
// Graded grids keep their planes; their cell counts (or cell_size) and each plane's smallest
// cell scale with the level.
#include <optional>
#include <string>

#include "isospring/fitting/identify_immersed_check.hpp"
#include "isospring/geometry/immersed_cad.hpp"

namespace isospring::workflows {

/// The background grid of ladder level `level` >= 1 over the grid `level0` immersed with `base`;
/// `description` receives e.g. "degree 2, 14 x 7 x 7 cells".
std::optional<geometry::ImmersionOptions> immersed_ladder_grid(
    const geometry::ImmersionOptions& base, const geometry::ImmersedDomain& level0, int level,
    std::string* description);

/// An upper bound of the active DOFs of ladder level `level` of an ungraded grid, before its
/// immersion: the functions of the level's cells that overlap a cell of `level0` meeting the part
/// (a cell of the part's can only meet it there). nullopt for graded grids.
std::optional<long> immersed_ladder_dofs_bound(const geometry::ImmersionOptions& base,
                                               const geometry::ImmersedDomain& level0, int level);

/// The ladder of `solid`, immersed with `base` into `level0`. The ladder refers to `solid`,
/// `base` and `level0`, which must outlive it.
fitting::ImmersedLadder immersed_grid_ladder(const geometry::CadSolid& solid,
                                             const geometry::ImmersionOptions& base,
                                             const geometry::ImmersedDomain& level0);

}  // namespace isospring::workflows
