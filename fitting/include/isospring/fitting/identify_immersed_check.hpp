#pragma once
// The discretisation check of the measured-data loop (discretization_check.hpp) on an immersed
// model: a ladder of background grids over the same part, each immersed and assembled anew.
//
// The rule is the body-fitted check's: level 0 is the case's own grid; each further level is
// finer; the error of level k at the markers is estimated from the finest level K solved,
// |u_K - u_k| plus the finest level's own error (its last difference, or that difference
// extrapolated geometrically, r |D| / (1 - r), when the last two differences give a ratio
// r < 1). The first level whose estimate is below `target_fraction` x noise is the model the loop
// runs on; a level is only chosen while the ladder goes on with a convergence ratio behind its
// estimate, and the finest level on its extrapolated error alone when that is at most half the
// target. DiscretizationOptions::max_dofs bounds the levels solved (the active DOFs, counted
// after the level's immersion), max_levels their number; between the chosen level and the one
// before it an intermediate grid is tried when the ladder gives one. When no level within the
// budget passes, the finest level solved is used, the check's note says so, and the loop widens
// its F-tests by the estimated error (identify.cpp), as for a body-fitted model.
//
// Every level is re-immersed. Where two grids are nested (cells split evenly), the finer grid's
// inside and outside cells could be inherited from the coarser one, but not its cut cells'
// quadrature or the boundary points' cells, which are most of an immersion's cost; `isospring
// identify`'s ladder (workflows/immersed_grid_ladder.hpp) steps by sqrt 2 and is not nested. The
// levels' descriptions report each immersion's time. The coarser grid does serve before an
// immersion: ImmersedLadder::dofs_bound bounds a level's DOFs from it.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "isospring/fitting/discretization_check.hpp"
#include "isospring/fitting/identify.hpp"
#include "isospring/fitting/immersed_calibration.hpp"

namespace isospring::fitting {

/// One background grid of a ladder, immersed: the domain and a label such as "degree 3,
/// 20 x 10 x 10 cells".
struct ImmersedLevel {
  geometry::ImmersedDomain domain;
  std::string description;
  double immersion_seconds = 0.0;  // wall time of the immersion (reported with the level)
};

/// Level `level` >= 1 of ever finer background grids over the same part in the same box (the
/// markers keep their physical positions), immersed; nullopt when there is none. `dofs_bound`
/// answers, before immersing, an upper bound of the level's active DOFs (nullopt: not known),
/// so that a level beyond the budget is not immersed at all.
struct ImmersedLadder {
  std::function<std::optional<ImmersedLevel>(int level)> level;
  std::function<std::optional<long>(int level)> dofs_bound;
  /// Between levels k - 1 and k (asked for as intermediate(k)), e.g. 1.5 x the cells of level
  /// k - 1; empty or nullopt: none.
  std::function<std::optional<ImmersedLevel>(int level)> intermediate;
};

/// The loop on an immersed model (identify_immersed.hpp) with the discretisation check on
/// `ladder` (options.discretization: enabled, target_fraction, max_dofs, max_levels; its body-
/// fitted ladders are not used). `domain` is the case's own grid, level 0.
IdentifyResult identify_immersed(const geometry::ImmersedDomain& domain,
                                 const std::vector<ImmersedCalibrationCase>& cases,
                                 const std::vector<Marker>& markers, const IdentifyOptions& options,
                                 const ImmersedLadder& ladder);

/// The check alone, at the given modulus ratio E / E_prior of the cases' material (the nominal
/// fit's) and noise level [m] (rms per component): for tests and reports.
DiscretizationCheck check_immersed_discretization(
    const geometry::ImmersedDomain& domain, const std::vector<ImmersedCalibrationCase>& cases,
    const std::vector<Marker>& markers, double modulus_ratio, double noise,
    const DiscretizationOptions& options, const ImmersedLadder& ladder,
    const std::function<void(const std::string&)>& progress = {});

}  // namespace isospring::fitting
