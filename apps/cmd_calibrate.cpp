// `isospring calibrate CASE.json -o OUTDIR`: the NMSM of a case, calibrated against the IGA
// reference with the displacement objective (settings: the case's "calibration" object,
// docs/calibration.md). The work is workflows::run_calibrate and workflows::write_calibrate_outputs
// (isospring/workflows/calibrate_command.hpp): report.json, report.md, model.json, springs.vtp,
// <load-case>_errors.csv, result.vtm (ParaView) and the error figures. An immersed case is
// workflows::run_calibrate_immersed and write_calibrate_immersed_outputs
// (isospring/workflows/calibrate_immersed.hpp).
#include <chrono>
#include <memory>

#include "cli_util.hpp"
#include "command.hpp"
#include "isospring/io/atomic_file.hpp"
#include "isospring/io/case_file.hpp"
#include "isospring/io/immersed_case.hpp"
#include "isospring/io/json_text.hpp"
#include "isospring/io/output_guard.hpp"
#include "isospring/io/report.hpp"
#include "isospring/workflows/calibrate_command.hpp"
#include "isospring/workflows/calibrate_immersed.hpp"

namespace isospring::apps {
namespace {

struct CalibrateOptions {
  std::string case_file;
  std::string output;
  bool quiet = false;
  double max_step_us = 0.0;  // > 0: the case's calibration.max_step_us
};

void report_errors(const io::Progress& progress, const nlohmann::json& report, bool holdout,
                   const std::filesystem::path& out_dir) {
  progress("%e_rms " + io::format_number(report["percent_e_rms"].get<double>(), 4) + " (fitted)" +
           (holdout
                ? ", " + io::format_number(report["holdout"]["percent_e_rms"].get<double>(), 4) +
                      " (held out)"
                : std::string()) +
           "; wrote " + out_dir.string());
}

void run_calibrate_immersed(const CalibrateOptions& options,
                            std::chrono::steady_clock::time_point start,
                            const io::Progress& progress) {
  const std::filesystem::path out_dir = output_folder(options.output, {options.case_file},
                                                      workflows::calibrate_immersed_output_files());
  io::ImmersedCase c = io::read_immersed_case(options.case_file);
  if (options.max_step_us > 0.0) c.raw["calibration"]["max_step_us"] = options.max_step_us;
  std::vector<std::string> ids;
  for (const auto& load : c.load_cases) ids.push_back(load.id);
  io::check_outputs_spare_inputs(
      input_files(options.case_file),
      in_folder(out_dir, workflows::calibrate_immersed_output_files(ids)));
  const workflows::ImmersedCalibrateResult result = workflows::run_calibrate_immersed(c, progress);
  const nlohmann::json report = workflows::write_calibrate_immersed_outputs(out_dir, result, start);
  report_errors(progress, report, !result.calibration.calibration.holdout.empty(), out_dir);
}

void run_calibrate(const CalibrateOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const io::Progress progress("calibrate", options.quiet);
  if (io::is_immersed_case(io::parse_json_text(io::read_text_file(options.case_file, "case file"),
                                               options.case_file, "case file")))
    return run_calibrate_immersed(options, start, progress);
  const std::filesystem::path out_dir =
      output_folder(options.output, {options.case_file}, workflows::calibrate_output_files());
  progress("reading " + options.case_file);
  io::Case c = io::read_case_file(options.case_file, solve_limits(0));
  if (options.max_step_us > 0.0) {
    if (c.calibration.is_null()) c.calibration = nlohmann::json::object();
    c.calibration["max_step_us"] = options.max_step_us;
  }
  std::vector<std::string> ids;
  for (const auto& load : c.problem.load_cases) ids.push_back(load.id);
  io::check_outputs_spare_inputs(case_inputs(c),
                                 in_folder(out_dir, workflows::calibrate_output_files(ids)));
  const workflows::CalibrateCommandResult result = workflows::run_calibrate(std::move(c), progress);
  const nlohmann::json report = workflows::write_calibrate_outputs(out_dir, result, start);
  report_errors(progress, report, !result.calibration.holdout.empty(), out_dir);
}

void setup_calibrate(CLI::App& app) {
  auto options = std::make_shared<CalibrateOptions>();
  CLI::App* cmd = app.add_subcommand(
      "calibrate",
      "Build the NURBS mass-spring model of a case and calibrate its stiffnesses "
      "against the isogeometric reference");
  cmd->footer(
      "Settings: the case file's \"calibration\" object (docs/calibration.md).\n"
      "Writes OUTDIR/report.json (springs, groups, %e_rms/%e_max of the fitted and held-out load\n"
      "cases, iterations, final cost, fit time, matrix-approach comparison), OUTDIR/report.md,\n"
      "OUTDIR/model.json (the calibrated spring model), OUTDIR/springs.vtp (springs with the\n"
      "error fields), OUTDIR/<load-case>_errors.csv (error per control point), OUTDIR/result.vtm\n"
      "(ParaView: geometry, control net and springs with reference_<id>, model_<id>, error_<id>)\n"
      "and OUTDIR/errors_histogram.png, OUTDIR/errors_vs_position.png (need gnuplot).\n"
      "An immersed case (docs/immersed.md) writes report.json, report.md, model.json,\n"
      "springs.vtp, <load-case>_errors.csv and result.vtp (the part with reference_<id> and\n"
      "springs_<id>).\n"
      "Exit status 3 when the fit does not converge.");
  cmd->add_option("CASE", options->case_file, "Case file (.json)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", options->output, "Output folder (created if missing)")->required();
  cmd->add_flag("-q,--quiet", options->quiet, "No progress lines on stderr");
  cmd->add_option("--max-step-us", options->max_step_us,
                  "Budget per engine step in microseconds (calibration.max_step_us): with a "
                  "\"generalisation\" object the most accurate model kind within it, otherwise "
                  "a refusal of a model over it")
      ->check(CLI::PositiveNumber);
  cmd->callback([options] { run_calibrate(*options); });
}

}  // namespace
ISOSPRING_REGISTER_COMMAND(50, setup_calibrate);
}  // namespace isospring::apps
