#pragma once
// Discretisation control for the measured-data loop: before any effect is blamed for a misfit,
// make sure the reference model's own numerical error at the markers is well below the noise.
//
// The model is solved on a ladder of discretisations of the same body and loads (level 0 is the
// case's own; each further level is finer). The error of level k at the markers is estimated
// from the next level, e_k ~ |u_{k+1} - u_k| (rms over marker components), divided by (1 - r)
// where the ladder shows geometric convergence with ratio r = e_k / e_{k-1} < 1 (Richardson
// extrapolation of the error: sum of the remaining differences). The first level with e_k below
// `target_fraction` x noise is the model the identification uses. The finest level solved may be
// chosen on its extrapolated error alone, without solving the next (largest) level, when a
// convergence ratio is known and that error is at most half the target. When the DOF budget stops
// the ladder first, the finest level solved is used, the check says so, and the identification
// widens its significance test by the estimated error (identify.cpp) instead of adding effects to
// absorb it.
//
// Every level is solved with the material of the nominal fit (E, nu), so the estimate is in the
// same units and scale as the measured displacements.
//
// Nearly incompressible materials: at nu >= bbar_from_poisson (off by default) every level of a
// solid or plane-strain model, the case's own included, uses B-bar (analysis::Volumetric::kBbar,
// the volumetric strain projected one degree lower), and the chosen level carries it into the loop.
// Where the threshold comes from (DiscretizationVolumetric.DISABLED_CantileverDofsTable, the
// suite's cantilever, a third of 0.2 % noise): at nu = 0.45 both formulations choose degree 3 on
// 30 x 6 x 6 elements (8,019 DOFs, 0.30 / 0.29 x the noise), B-bar at 5x the check's time; at
// nu = 0.49 the displacement formulation stays above the target within the DOF budget (0.37 x
// the noise at 15,609 DOFs) and B-bar reaches it there (0.28 x). B-bar costs 3-10 x more per DOF
// to assemble and factorise (its projection couples control points 3p - 2 apart), so it pays
// only where the displacement formulation cannot reach the target; the clamped edges' singular
// stresses, not locking, limit both formulations on nets that fine. Off by default (below).
#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "isospring/analysis/problem.hpp"
#include "isospring/fitting/measure.hpp"

namespace isospring::fitting {

/// Level `level` >= 1 of a sequence of ever finer discretisations of the same body and loads, in
/// the same parametrisation (markers keep their parametric positions), or nullopt when there is
/// no finer level. `description` receives a short label, e.g. "degree 3, 20 x 4 x 4 elements".
using DiscretizationLadder =
    std::function<std::optional<analysis::Problem>(int level, std::string* description)>;

/// The default ladder: level l splits every knot span of every patch of `problem` into 2^l
/// (knot insertion: geometry and parametrisation unchanged). Supports and point loads on single
/// control points follow their net corner; on other control points they have no counterpart on a
/// refined net and check_discretization throws nurbs::InputError.
DiscretizationLadder knot_insertion_ladder(const analysis::Problem& problem);

/// Between knot_insertion_ladder's levels k - 1 and k (k >= 2): every knot span split in
/// 3 x 2^(k - 2), 1.5 x the splits of level k - 1.
DiscretizationLadder knot_insertion_intermediate(const analysis::Problem& problem);

struct DiscretizationOptions {
  bool enabled = true;
  /// The reference's marker error must stay below this fraction of the noise (rms).
  double target_fraction = 1.0 / 3.0;
  /// No level with more DOFs is solved (the finer level that estimates a level's error counts).
  long max_dofs = 25000;  // a degree-3 solid of 15,609 DOFs solves in ~10 s here
  int max_levels = 5;     // levels beyond the case's own
  /// Empty: knot_insertion_ladder(problem). Case files give a k-refinement ladder
  /// (io::case_refinement_ladder).
  DiscretizationLadder ladder;
  /// A discretisation between ladder levels k - 1 and k, asked for as `intermediate(k, ...)`
  /// (nullopt when there is none), e.g. 1.5 x the elements of level k - 1. When level k >= 1 is
  /// chosen, this one is solved too and used instead when its own estimate (its difference to the
  /// finest level plus that level's extrapolated error) is within the target: a solid's ladder
  /// grows ~4.5x in DOFs per level and the identification's cost with the square of them, so a
  /// level chosen far inside the target is paid for many times over. Empty: none when `ladder`
  /// is given, knot_insertion_intermediate(problem) otherwise.
  DiscretizationLadder intermediate;
  /// Convergence ratios (the Richardson tail) come only from differences between levels >= this:
  /// the levels of one family (same degrees, nested nets, elements doubling). A difference that
  /// reaches below it, e.g. from the case's own uniform net to a graded one, mixes two families
  /// and can show a ratio far smaller than the family's (0.09 against ~0.35 measured on the
  /// suite's cantilever), which would certify a level that is not in target. 0: every level.
  int ratio_from_level = 0;
  /// B-bar on every level (solids and plane strain) when the nominal fit's Poisson ratio is at
  /// least this; above 0.5: never (the default). A case that asks for B-bar itself keeps it
  /// whatever nu. Off by default: on the suite's cantilever at nu = 0.49 (0.48 would turn it on)
  /// the check chose a 15,609-DOF B-bar level and identify's loop on it grew to 20 GB in
  /// support_compliance's fit and was killed by the kernel (out of memory).
  double bbar_from_poisson = 1.0;
};

struct DiscretizationLevel {
  int level = 0;
  std::string description;
  int dofs = 0;
  /// Estimated error at the markers [m]: rms and max over marker components; NaN when no finer
  /// level was solved.
  double error_rms = 0.0, error_max = 0.0;
  /// Part of error_rms the material fit cannot absorb (the difference after the best scale of
  /// the displacements, i.e. a refit of E): what could be mistaken for an effect.
  double error_rms_after_material = 0.0;
  std::string estimate;  // "next level", "next level, geometric extrapolation (ratio 0.21)", ...
  double seconds = 0.0;  // assembly and solve
};

struct DiscretizationCheck {
  bool done = false;    // false: disabled, or not possible (see note)
  std::string note;     // why not done, or why the target was not reached
  double noise = 0.0;   // [m] the noise level compared with
  double target = 0.0;  // target_fraction x noise
  std::vector<DiscretizationLevel> levels;
  int chosen = 0;             // index into levels of the model used
  bool within_target = true;  // levels[chosen] has an estimate below the target
  bool budget_exhausted = false;
  /// Per marker: the estimated discretisation error of the chosen level (model minus a finer
  /// one), used to widen the significance test when within_target is false.
  std::vector<Eigen::Vector3d> marker_error;
  /// The problem of the chosen level; empty when that is the input problem itself (level 0 in
  /// the case's formulation).
  std::optional<analysis::Problem> chosen_problem;
  /// The levels' formulation of the volumetric strain: "displacement" or "bbar", and why.
  std::string volumetric = "displacement";
  std::string volumetric_rule;
};

/// Runs the ladder. `youngs_modulus` / `poisson_ratio` replace the problem's material for the
/// solves (the nominal fit's values); `noise` [m] is the rms noise per component. Markers must be
/// placed on `problem` (place_markers); every level must share its parametrisation (checked: a
/// level whose geometry at a marker moves by more than 1e-9 x the model size is an error) and its
/// conditions on single control points (net corners at the same place; InputError otherwise).
DiscretizationCheck check_discretization(
    const analysis::Problem& problem, const std::vector<Marker>& markers,
    const std::vector<MarkerPlacement>& placements, double youngs_modulus, double poisson_ratio,
    double noise, const DiscretizationOptions& options,
    const std::function<void(const std::string&)>& progress = {});

}  // namespace isospring::fitting
