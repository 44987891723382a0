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
  /// Rest-length window; a non-empty gamma_sweep fits every value and keeps the lowest error.
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

struct SweepEntry {
  double gamma = 0.0;
  int groups = 0;
  double percent_e_rms = 0.0;  // root mean square over the fitted cases
  double percent_e_max = 0.0;  // largest over the fitted cases
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
  std::vector<SweepEntry> sweep;
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
/// fails or the fit does not converge.
CalibrationResult calibrate(const analysis::Problem& problem, const CalibrationSettings& settings);

}  // namespace isospring::fitting
