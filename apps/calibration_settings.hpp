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
//     "acceleration_objective": true        // also fit the [S15 4.1-4.5] objective, report it
//   }
//
// Every field is optional; an absent object means the defaults. Unknown fields and wrong types
// are nurbs::InputError naming the case file and the field.
#include <nlohmann/json.hpp>
#include <string>

#include "isospring/fitting/calibration.hpp"

namespace isospring::apps {

struct CalibrationRequest {
  fitting::CalibrationSettings settings;
  bool matrix_approach = true;
  /// Also fit the acceleration objective [S15 4.1-4.5] with the same grouping and report it.
  bool acceleration_objective = true;
};

/// Validates and converts `calibration` (null: defaults); `file` names the case in messages.
CalibrationRequest parse_calibration(const nlohmann::json& calibration, const std::string& file);

}  // namespace isospring::apps
