#pragma once
// The whole NMSM calibration of a problem: IGA reference (analysis::solve_static), spring mesh,
// masses, consistent loads, displacement fit (optionally a gamma sweep, Algorithm 5.1), metrics on
// the fitted and on held-out load cases.
#include <functional>
#include <string>
#include <vector>

#include "isospring/analysis/problem.hpp"
#include "isospring/fitting/displacement_fit.hpp"
#include "isospring/fitting/error_metrics.hpp"
#include "isospring/fitting/matrix_approach.hpp"
#include "isospring/fitting/spring_masses.hpp"
#include "isospring/fitting/spring_mesh.hpp"

namespace isospring::fitting {

struct CalibrationSettings {
  /// Rest-length window; a non-empty gamma_sweep fits every value and keeps the lowest error
  /// (Algorithm 5.1; CalibrationResult::sweep has one entry per value, SweepEntry says how a
  /// failing gamma and a repeated grouping are handled).
  double gamma = 0.01;
  std::vector<double> gamma_sweep;
  /// One stiffness per spring, pulled towards its gamma group's value with this weight (0: free).
  bool per_spring = false;
  double regularization = 0.0;
  /// Per-spring fits only: > 0 fits by L-BFGS with the penalty (w / S) sum (log k_s - log
  /// prior_s)^2 towards the start (prior_spring_fit.hpp) instead of Levenberg-Marquardt with
  /// `regularization`; cheap with many load cases. Chosen by validation error
  /// (generalising_calibration.hpp), not by the fitted error.
  double prior_weight = 0.0;
  int prior_max_iterations = 300;  // L-BFGS iterations of that fit
  /// Per-spring fits only: the stiffness per spring to start from (e.g. a grouped optimum the
  /// caller already has); empty: the grouped optimum of `gamma`, fitted first.
  std::vector<double> per_spring_start;
  bool upper_bounds = false;  // [S15 4.19] bounds per group
  /// Lower bound of every stiffness as a fraction of the stiffest initial group
  /// (DisplacementFitOptions::min_stiffness_ratio).
  double min_stiffness_ratio = 1e-6;
  MassModel mass_model = MassModel::kLumpedIga;
  SpringMeshOptions mesh;
  std::vector<std::string> fit_cases;      // ids; empty: every case not in holdout_cases
  std::vector<std::string> holdout_cases;  // ids evaluated, not fitted
  double damping_alpha = 0.0;              // > 0: [S15 4.18] damping on the fitted springs
  double damping_ratio = 0.0;              // > 0: c = 2 zeta sqrt(k m_reduced) instead (not both)
  int max_iterations = 200;
  /// > 0: a budget for one engine step [us] (step_cost.hpp's estimate of the runtime's force
  /// evaluation): calibrate() refuses a model over it (nurbs::InputError, before any fit), and
  /// calibrate_for_generalisation() leaves out the model kinds over it, so that it picks the
  /// most accurate model within the budget.
  double max_step_us = 0.0;
  int field_samples = 11;  // per direction for the field metrics
  /// false: only the control-point metrics (cross-validation folds need no more).
  bool field_metrics = true;
  /// Also fit ||K_IGA - K_NMSM||_F (matrix approach) with the same grouping, and per element when
  /// every patch has degree 1, and evaluate those models on the same load cases.
  bool matrix_approach = false;
  /// Per load case of the problem: the reference displacements (all DOFs, analysis::DofMap
  /// numbering) to fit instead of analysis::solve_static of the problem. Empty: solve. Used by
  /// the identification to recalibrate against its corrected model, which may hold what a
  /// Problem cannot (a stiffness gradient).
  std::vector<Eigen::VectorXd> reference_displacements;
  /// Progress lines ("fit gamma 0.01 (4 groups): iteration 3, cost 1.2e-4"); empty: silent.
  std::function<void(const std::string&)> progress;
  /// Per fit iteration (stage such as "fit (gamma 0.01)", iteration, cost): when set, used
  /// instead of one `progress` line per iteration (a terminal shows it on one updating line).
  std::function<void(const std::string&, int, double)> iteration;
};

struct CaseErrors {
  std::string id;
  ErrorMetrics control;                     // on the control points (nodes)
  ErrorMetrics field;                       // on the displacement field (whole domain)
  ErrorMetrics surface;                     // on the physical surface (boundary faces in 3D)
  std::vector<Eigen::Vector3d> node_error;  // u_nmsm - u_ref per node
};

/// One gamma of the sweep (Algorithm 5.1), in the order of CalibrationSettings::gamma_sweep
/// (without a sweep: one entry, CalibrationSettings::gamma).
///
/// A gamma whose fit fails (it throws std::runtime_error, does not converge, leaves a
/// non-positive or non-finite stiffness, or a network that is singular under the supports) is
/// recorded with `failure` and the sweep goes on with the next gamma; calibrate() throws only
/// when every gamma fails. A gamma whose grouping is identical to an earlier entry's (the same
/// group for every spring and volume term) is not fitted again: the entry copies that fit (the
/// same data and grouping give the same fit) and names it in `reused_from`.
///
/// The sweep keeps the usable entry (empty `failure`) with the lowest root mean square of
/// control[].percent_e_rms, the first one on a tie; CalibrationResult::gamma is its gamma, and
/// CalibrationResult::fit[c].control equals its control[c].
struct SweepEntry {
  double gamma = 0.0;
  int groups = 0;  // rest-length groups of gamma (group_by_rest_length)
  /// Stiffnesses fitted: `groups`, or one per spring and volume term with per_spring; 0 when the
  /// fit threw before it had any.
  int parameters = 0;
  double percent_e_rms = 0.0;  // root mean square over the fitted cases, of the fit's residuals
  double percent_e_max = 0.0;  // largest over the fitted cases, of the fit's residuals
  /// Per fitted case (the order of CalibrationResult::fit): the control-point metrics of this
  /// gamma's model from a fresh linear solve, as CalibrationResult::fit has them for the kept
  /// gamma. Empty when the gamma failed.
  std::vector<ErrorMetrics> control;
  /// The fit (DisplacementFitResult's fields of the same names; a per-spring fit can start from
  /// spring_stiffness, see per_spring_start). Empty when the fit threw.
  std::vector<double> group_stiffness;
  std::vector<double> spring_stiffness;
  std::vector<double> volume_modulus;
  /// Empty: the gamma gave a usable model. Otherwise why it did not (the message calibrate()
  /// would throw for it alone); such an entry is never kept.
  std::string failure;
  /// Index in CalibrationResult::sweep of the entry whose fit this one copies (identical
  /// grouping); -1: fitted for this gamma.
  int reused_from = -1;
};

/// A matrix-approach model evaluated like the displacement fit. `solved` is false when its
/// stiffness matrix is singular under the supports (negative springs can make it so).
struct MatrixComparison {
  std::string method;  // "global" or "per_element"
  MatrixFitResult fit;
  bool solved = false;
  std::vector<CaseErrors> fit_cases;
  std::vector<CaseErrors> holdout;
};

struct CalibrationResult {
  SpringMesh mesh;  // springs with fitted stiffness (and damping), masses, fixed particles
  Grouping grouping;
  double gamma = 0.0;
  int parameters = 0;
  std::vector<CaseErrors> fit;
  std::vector<CaseErrors> holdout;
  std::vector<SweepEntry> sweep;  // one entry per gamma, see SweepEntry
  DisplacementFitResult fit_result;
  std::vector<MatrixComparison> matrix;  // when settings.matrix_approach
  double reference_seconds = 0.0;
  double fit_seconds = 0.0;           // all fits, sweep included
  std::vector<std::string> warnings;  // e.g. stiffness groups held at the lower bound
  /// Per load case of the problem (same order, ids in load_ids): the load the springs were
  /// fitted and evaluated under, as forces on the particles (flat, particle * dimension +
  /// component) [N]: the consistent IGA load, gravity included, summed per particle. With these
  /// a spring model (model.json) reproduces the calibration's responses on its own.
  std::vector<std::string> load_ids;
  std::vector<Eigen::VectorXd> particle_loads;
};

/// Runs the calibration. Throws nurbs::InputError for bad settings or problems (unknown case ids,
/// non-zero prescribed displacements, no fitted case) and std::runtime_error when the IGA solve
/// fails or the fit of every gamma fails (one gamma: its message; a sweep: every gamma's).
CalibrationResult calibrate(const analysis::Problem& problem, const CalibrationSettings& settings);

}  // namespace isospring::fitting
