// `isospring calibrate CASE.json -o OUTDIR`: the NMSM of a case, calibrated against the IGA
// reference with the displacement objective (settings: the case's "calibration" object,
// docs/calibration.md). The work is workflows::run_calibrate and workflows::write_calibrate_outputs
// (isospring/workflows/calibrate_command.hpp): report.json, report.md, model.json, springs.vtp,
// <load-case>_errors.csv, result.vtm (ParaView) and the error figures.
#include <chrono>
#include <memory>

#include "cli_util.hpp"
#include "command.hpp"
#include "isospring/io/case_file.hpp"
#include "isospring/io/output_guard.hpp"
#include "isospring/io/report.hpp"
#include "isospring/workflows/calibrate_command.hpp"
#include "isospring/workflows/immersed_refusals.hpp"

namespace isospring::apps {
namespace {

struct CalibrateOptions {
  std::string case_file;
  std::string output;
  bool quiet = false;
  double max_step_us = 0.0;  // > 0: the case's calibration.max_step_us
};

void run_calibrate(const CalibrateOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const io::Progress progress("calibrate", options.quiet);
  workflows::refuse_immersed_case(options.case_file, "calibrate");  // before any folder is made
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
  progress("%e_rms " + io::format_number(report["percent_e_rms"].get<double>(), 4) + " (fitted)" +
           (result.calibration.holdout.empty()
                ? std::string()
                : ", " + io::format_number(report["holdout"]["percent_e_rms"].get<double>(), 4) +
                      " (held out)") +
           "; wrote " + out_dir.string());
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
