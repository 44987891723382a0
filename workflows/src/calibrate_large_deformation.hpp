#pragma once
// The large-deformation branch of run_calibrate (a case with a finite-strain material.model).
#include "isospring/workflows/calibrate_command.hpp"

namespace isospring::workflows {

/// Refuses what the large-deformation calibration does not offer (no calibration.amplitudes,
/// generalisation, per-spring freedom, a step budget, an explicit matrix_approach or
/// acceleration_objective) with nurbs::InputError naming the field; then
/// fitting::calibrate_large_deformation, the held-out cases against their finite-strain
/// references and the result shaped like the linear calibration's.
CalibrateCommandResult run_calibrate_large_deformation(io::Case c, io::CalibrationRequest request,
                                                       const io::Progress& progress);

}  // namespace isospring::workflows
