#pragma once
// The `"calibration"` object of a case file (documented in docs/calibration.md):
//
//   "calibration": {
//     "fit_load_cases": ["u1_x", "u1_y"],   // fitted together; default: every case not held out
//     "holdout_load_cases": ["v1_x"],       // evaluated with the fitted model, never fitted
//     "grouping": {"gamma": 0.01},          // or {"gamma_sweep": [0.3, 0.1, 0.01]} (keep the best)
//                                           // or {"per_spring": true, "gamma": 0.01} or
//                                           "per_spring"
//     "regularization": 0.0,                // per spring only: pull towards the gamma group, >= 0
//     "mass": "lumped",                     // or "net_cells"
//     "damping_alpha": 200,                 // > 0: damping c = 2 sqrt(k (m_i + m_j)) / (alpha L0)
//     "damping_ratio": 0.05,                // or: c = 2 zeta sqrt(k m_reduced) (not both)
//     "upper_bounds": false,                // [S15 4.19] stiffness bounds per group
//     "merge_coincident": false,            // one particle for coincident control points
//     "max_iterations": 200,
//     "field_samples": 11,                  // per direction, for the field error metrics
//     "matrix_approach": true,              // also fit ||K_IGA - K_NMSM||_F and report it
//     "acceleration_objective": true,       // also fit the [S15 4.1-4.5] objective, report it
//     "amplitudes": [5, 20],                // with a finite-strain material.model: target %eps_G
//                                           // of the large-deformation fit, ascending; or
//                                           // {"max": 20, "steps": 4} (5, 10, 15, 20)
//     "target_percent_e_rms": 2.0,          // > 0: warn when the worst fitted or held-out
//                                           // %e_rms exceeds it
//     "generalisation": {                   // choose the freedom by cross-validation
//       "load_suite": true,                 // add the load suite (default: when no
//                                           // fit_load_cases are given)
//       "gammas": [0.8, 0.5, 0.2, 0.1, 0.01], "prior_weights": [1e-2, 1e-3, 1e-4],
//       "reaches": [1], "folds": 3, "prior_iterations": 300
//     }
//   }
//
// Every field is optional; an absent object means the defaults. Unknown fields and wrong types
// are nurbs::InputError naming the case file and the field.
#include <nlohmann/json.hpp>
#include <string>

#include <optional>

#include "isospring/fitting/calibration.hpp"
#include "isospring/fitting/generalising_calibration.hpp"

namespace isospring::io {

struct CalibrationRequest {
  fitting::CalibrationSettings settings;
  bool matrix_approach = true;
  /// Also fit the acceleration objective [S15 4.1-4.5] with the same grouping and report it.
  bool acceleration_objective = true;
  double target_percent_e_rms = 0.0;
  /// Set: calibrate with fitting::calibrate_for_generalisation.
  std::optional<fitting::GeneralisationOptions> generalisation;
  bool load_suite = false;  // append fitting::generate_load_suite's cases (train / validate)
  /// "amplitudes": target %eps_G of the large-deformation calibration (with a finite-strain
  /// material.model), ascending; empty when absent.
  std::vector<double> amplitudes;
  /// Whether matrix_approach / acceleration_objective were given (their defaults are for linear
  /// calibration; the large-deformation one refuses them only when asked for).
  bool matrix_approach_given = false;
  bool acceleration_objective_given = false;
};

/// Validates and converts `calibration` (null: defaults); `file` names the case in messages.
CalibrationRequest read_calibration_settings(const nlohmann::json& calibration,
                                             const std::string& file);

}  // namespace isospring::io
