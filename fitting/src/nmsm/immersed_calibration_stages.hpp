#pragma once
// State handed from calibrate_immersed's first stages (immersed_calibration.cpp) to its metrics
// (immersed_calibration_metrics.cpp). Private to the fitting module.
#include <Eigen/Core>
#include <vector>

#include "isospring/fitting/immersed_calibration.hpp"
#include "nmsm/calibration_stages.hpp"

namespace isospring::fitting::detail {

/// calibrate()'s FitSetup (nodes = particles = active control points, in the immersed solve's
/// node order) with the background control points' node numbers and each case's load vector.
struct ImmersedFit {
  explicit ImmersedFit(int dim) : setup(dim) {}
  FitSetup setup;
  std::vector<int> node_of_control_point;  // -1: inactive
  std::vector<Eigen::VectorXd> loads;      // per case, active DOFs (= particle DOFs)
};

/// Stage: result.calibration.fit / holdout (control points, and with settings.field_metrics the
/// spline fields over the part and its surface) and result.model_control_displacements of the
/// calibrated network.
void evaluate_immersed_cases(const geometry::ImmersedDomain& domain,
                             const std::vector<ImmersedCalibrationCase>& cases,
                             const CalibrationSettings& settings, const ImmersedFit& fit,
                             ImmersedCalibrationResult& result);

}  // namespace isospring::fitting::detail
