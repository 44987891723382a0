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
};

/// Calibrates `c` (taken by value: the load suite extends its problem). Throws
/// nurbs::InputError for a bad "calibration" object and like fitting::calibrate. `progress` gets
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
