#pragma once
// The use case behind `isospring identify` as one library call (Options in, Result out), so that
// a C++ program, the Python module and the CLI run the same code: read the case's
// "measurements", place the markers on the model, run fitting::identify, recalibrate the spring
// model against the corrected reference; then the report (JSON and Markdown) and the files.
//
//   const io::Case c = io::read_case_file("case.json");
//   const io::Progress progress("identify", true);
//   const workflows::IdentifyCommandResult r = workflows::run_identify(c, {}, progress);
//   workflows::write_identify_outputs("out", r, progress);  // report.json, report.md, ...
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "isospring/fitting/identify.hpp"
#include "isospring/fitting/identify_recalibration.hpp"
#include "isospring/fitting/measure.hpp"
#include "isospring/io/case_file.hpp"
#include "isospring/io/markers.hpp"
#include "isospring/io/model_file.hpp"
#include "isospring/io/report.hpp"

namespace isospring::workflows {

struct IdentifyCommandOptions {
  /// Leave out markers farther from the model than the placement tolerance (listed in the
  /// result) instead of failing.
  bool drop_outside = false;
  std::optional<long> max_dofs;  // overrides measurements.max_dofs
  bool discretization_check = true;
  /// Recalibrate the spring model against the corrected reference (the case's "calibration"
  /// object applies); a failed recalibration is reported in the result, not thrown.
  bool recalibrate = true;
};

/// A marker left out with drop_outside: its CSV row and distance from the model.
struct DroppedMarker {
  int row = 0;
  std::string load_case;
  double distance = 0.0;
};

struct IdentifyCommandResult {
  std::filesystem::path input;  // the case file
  std::string case_name;
  nlohmann::json case_summary;  // io::case_summary of the case
  std::vector<std::string> load_case_ids;
  io::MeasurementSettings settings;
  std::vector<fitting::Marker> markers;  // the markers fitted (on the model)
  std::vector<DroppedMarker> dropped;
  double placement_tolerance = 0.0;  // metres
  fitting::IdentifyOptions identify_options;
  fitting::IdentifyResult identify;
  std::optional<fitting::Recalibration> recalibration;
  std::string recalibration_error;  // set when the recalibration failed
};

/// Runs the loop on `c`. Throws nurbs::InputError when the case has no "measurements", for a bad
/// "measurements" or "calibration" object or marker file, and for markers off the model unless
/// options.drop_outside. `progress` gets the milestones and warnings.
IdentifyCommandResult run_identify(const io::Case& c, const IdentifyCommandOptions& options,
                                   const io::Progress& progress);

/// The default placement tolerance: 1e-3 of the control nets' bounding-box diagonal.
double default_placement_tolerance(const std::vector<nurbs::Patch>& patches);

/// The files write_identify_outputs writes into its folder: the fixed ones and, with the load-case
/// ids (known once the case is read), the marker point sets markers_<id>_{before,after}.vtp.
std::vector<std::string> identify_output_files(const std::vector<std::string>& load_case_ids = {});

/// report.json of `isospring identify` (without the warnings, which add_warnings appends).
nlohmann::json identify_report_json(const IdentifyCommandResult& r);

/// report.md; `figure` adds the errors_before_after.png paragraph (written when gnuplot ran).
io::MarkdownReport identify_report_markdown(const IdentifyCommandResult& r, bool figure);

/// The recalibrated spring model with the carried gravity and load cases (model.json); only
/// when r.recalibration is set.
io::SpringModel identify_spring_model(const IdentifyCommandResult& r);

/// Writes every file of identify_output_files into `out_dir` (created): report.json, report.md,
/// model.json (when recalibrated), markers_*.vtp, residuals.csv/.svg and errors_before_after.png
/// (gnuplot, when present); the progress's warnings go into both reports.
void write_identify_outputs(const std::filesystem::path& out_dir, const IdentifyCommandResult& r,
                            const io::Progress& progress);

}  // namespace isospring::workflows
