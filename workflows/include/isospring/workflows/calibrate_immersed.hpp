#pragma once
// `isospring calibrate` on an immersed case ({"geometry": {"type": "immersed", ...}}) as one
// library call: the part immersed in its background grid (geometry::immerse_solid), the case's
// "calibration" object applied (the settings with an immersed form, fitting/
// immersed_calibration.hpp), fitting::calibrate_immersed; then the files: report.json,
// report.md, model.json (the calibrated spring model: `isospring export` converts it to MuJoCo,
// SOFA, VTK or JSON, the runtime loads it), springs.vtp (the springs with the error vectors),
// <id>_errors.csv (per particle) and result.vtp (the part's surface with the reference's and
// the spring model's displacement fields per fitted and held-out load case).
//
//   const io::Progress progress("calibrate", true);
//   const workflows::ImmersedCalibrateResult r =
//       workflows::run_calibrate_immersed(io::read_immersed_case("part.json"), progress);
//   workflows::write_calibrate_immersed_outputs("out", r, start);
#include <chrono>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "isospring/fitting/immersed_calibration.hpp"
#include "isospring/geometry/immersed_cad.hpp"
#include "isospring/io/calibration_settings.hpp"
#include "isospring/io/immersed_case.hpp"
#include "isospring/io/report.hpp"

namespace isospring::workflows {

struct ImmersedCalibrateResult {
  io::ImmersedCase c;
  io::CalibrationRequest request;  // as used (matrix approach and acceleration baseline off)
  geometry::ImmersedDomain domain;
  geometry::ImmersionStats stats;
  geometry::SolidMeasures occ;         // OpenCascade's volume, area, centroid
  geometry::SolidMeasures quadrature;  // the immersed domain's
  double immersion_seconds = 0.0;
  fitting::ImmersedCalibrationResult calibration;
  double worst_fitted = 0.0;   // largest control-point %e_rms over the fitted cases
  double worst_holdout = 0.0;  // ... over the held-out cases (0 without any)
  double worst = 0.0;
};

/// Immerses the case's part and calibrates its spring model. Throws nurbs::InputError naming the
/// case file for a "calibration" object with settings that have no immersed form (the
/// generalising choice and the load suite, which build on a body-fitted model's sides; the
/// matrix approach and the acceleration baseline asked for explicitly) and as
/// fitting::calibrate_immersed.
ImmersedCalibrateResult run_calibrate_immersed(const io::ImmersedCase& c,
                                               const io::Progress& progress);

/// The files write_calibrate_immersed_outputs writes: the fixed ones and, with the load-case
/// ids, <id>_errors.csv.
std::vector<std::string> calibrate_immersed_output_files(const std::vector<std::string>& ids = {});

/// Writes every file of calibrate_immersed_output_files into `out_dir` (created); `start` is when
/// the command started (report.json's total_seconds). Returns report.json's content.
nlohmann::json write_calibrate_immersed_outputs(const std::filesystem::path& out_dir,
                                                const ImmersedCalibrateResult& r,
                                                std::chrono::steady_clock::time_point start);

}  // namespace isospring::workflows
