#pragma once
// The use case behind `isospring calibrate` as one library call: the case's "calibration" object
// (calibration_settings.hpp) applied to its NMSM, the load suite and the generalising choice
// when asked for, fitting::calibrate, the acceleration-objective baseline; then the report
// (JSON and Markdown), model.json, the error tables and the viewer files.
//
//   const io::Progress progress("calibrate", true);
//   const workflows::CalibrateCommandResult r =
//       workflows::run_calibrate(io::read_case_file("case.json"), progress);
//   workflows::write_calibrate_outputs("out", r, progress);
#include <chrono>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "isospring/fitting/acceleration_fit.hpp"
#include "isospring/fitting/calibration.hpp"
#include "isospring/fitting/generalising_calibration.hpp"
#include "isospring/io/calibration_settings.hpp"
#include "isospring/io/case_file.hpp"
#include "isospring/io/model_file.hpp"
#include "isospring/io/report.hpp"

namespace isospring::workflows {

/// One amplitude of a large-deformation calibration: its fitted cases (the case's fitted load
/// cases scaled to this %eps_G) by the calibrated model's nonlinear equilibrium.
struct LargeDeformationAmplitude {
  double amplitude = 0.0;  // target %eps_G
  int cases = 0;
  double worst_percent_e_rms = 0.0;      // largest %e_rms over its cases
  double percent_e_rms = 0.0;            // root mean square of their %e_rms
  double reference_percent_eps_g = 0.0;  // mean %eps_G of the finite-strain references
  /// The linear fit to the same references (the nonlinear fit's start) by its own nonlinear
  /// equilibrium: worst %e_rms over the cases where it has one, and how many it has none on.
  double start_worst_percent_e_rms = 0.0;
  int start_without_equilibrium = 0;
};

/// With a finite-strain material.model (fitting::calibrate_large_deformation).
struct LargeDeformationSummary {
  std::string law;                 // "neo_hookean" or "svk"
  std::vector<double> amplitudes;  // calibration.amplitudes
  double reached_amplitude = 0.0;  // the largest fitted (see stopped)
  std::string stopped;             // why the fit stopped before the last amplitude ("": it did not)
  std::vector<LargeDeformationAmplitude> rows;           // per amplitude reached
  std::vector<std::string> holdout_without_equilibrium;  // left out of `holdout`
  /// Per load case of CalibrateCommandResult::problem: the finite-strain reference's control
  /// displacements [patch][control point] (the viewer's reference fields).
  std::vector<std::vector<std::vector<Eigen::Vector3d>>> reference_controls;
};

struct CalibrateCommandResult {
  std::filesystem::path input;  // the case file
  std::string case_name;
  nlohmann::json case_summary;  // io::case_summary of the case as read
  /// The case's problem, with the load suite's cases appended when it was asked for.
  analysis::Problem problem;
  /// The settings as used: with the load suite's cases and the generalising choice applied.
  io::CalibrationRequest request;
  /// Set with "generalisation": the candidates and the choice (its calibration moved out).
  std::optional<fitting::GeneralisationResult> generalisation;
  fitting::CalibrationResult calibration;
  std::optional<fitting::MatrixComparison> acceleration;  // the baseline, when computed
  double worst_fitted = 0.0;   // largest control-point %e_rms over the fitted cases
  double worst_holdout = 0.0;  // ... over the held-out cases (0 without any)
  double worst = 0.0;
  /// Set for a finite-strain material.model: `problem` then holds the fitted cases as scaled
  /// ("id@amplitude") and the held-out cases, `calibration` the nonlinear fit's model and errors.
  std::optional<LargeDeformationSummary> large_deformation;
};

/// Calibrates `c` (taken by value: the load suite extends its problem). With a finite-strain
/// material.model and calibration.amplitudes: the large-deformation calibration
/// (fitting::calibrate_large_deformation). Throws nurbs::InputError for a bad "calibration"
/// object and like fitting::calibrate. `progress` gets
/// milestones, the fit's iterations (unless quiet) and the warnings.
CalibrateCommandResult run_calibrate(io::Case c, const io::Progress& progress);

/// The files write_calibrate_outputs writes: the fixed ones and, with the load-case ids,
/// <id>_errors.csv.
std::vector<std::string> calibrate_output_files(const std::vector<std::string>& load_case_ids = {});

/// One load case's errors as report.json has them: id, control-point, field and surface
/// %e_rms / %e_max and o_max.
nlohmann::json case_errors_json(const fitting::CaseErrors& e);

/// report.json of `isospring calibrate`, except "vtk_file", "figures" and "total_seconds" (set
/// by write_calibrate_outputs).
nlohmann::json calibrate_report_json(const CalibrateCommandResult& r);

/// report.md from the result and its report.json (`report`); `figures` are linked at the end.
io::MarkdownReport calibrate_report_markdown(const CalibrateCommandResult& r,
                                             const nlohmann::json& report,
                                             const std::vector<std::string>& figures);

/// The calibrated spring model with its load cases and provenance (model.json); `report` is
/// calibrate_report_json's (its percent_e_rms / percent_e_max go into the provenance).
io::SpringModel calibrate_spring_model(const CalibrateCommandResult& r,
                                       const nlohmann::json& report);

/// Writes every file of calibrate_output_files into `out_dir` (created): model.json, springs.vtp,
/// <id>_errors.csv, result.vtm, the figures, report.json and report.md. `start` is when the
/// command started (report.json's total_seconds). Returns report.json's content.
nlohmann::json write_calibrate_outputs(const std::filesystem::path& out_dir,
                                       const CalibrateCommandResult& r,
                                       std::chrono::steady_clock::time_point start);

}  // namespace isospring::workflows
