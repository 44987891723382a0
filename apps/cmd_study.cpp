// `isospring study CASE.json -o OUTDIR --levels N --degrees 2,3,4`: uniform k-refinement study.
// Level l has elements * 2^l per direction (the case's discretisation is level 0). Errors are
// against the case's analytic solution (relative L2 and energy norms) when it names one. A scalar
// (`--quantity`: strain energy, max control displacement, or a displacement at `--point`) is
// followed at every level and, from 3 levels on, Richardson-extrapolated from the last three
// (observed order and mesh-independent value); without an analytic solution its relative error to
// the extrapolated value (or to the finest level when the sequence is not monotone) is the error.
// Rates are least-squares fits over the last three levels (benchmarks.md). Writes report.json,
// report.md, study.csv and convergence.png (gnuplot; skipped with a warning when missing).
// The work is workflows::run_study and workflows::write_study_outputs
// (isospring/workflows/study_command.hpp); on an immersed case workflows::run_study_immersed
// refines the background grid instead (isospring/workflows/study_immersed.hpp).
#include <cmath>
#include <memory>

#include "cli_util.hpp"
#include "command.hpp"
#include "isospring/io/atomic_file.hpp"
#include "isospring/io/case_file.hpp"
#include "isospring/io/immersed_case.hpp"
#include "isospring/io/json_text.hpp"
#include "isospring/io/output_guard.hpp"
#include "isospring/io/report.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/workflows/study_command.hpp"
#include "isospring/workflows/study_immersed.hpp"

namespace isospring::apps {
namespace {

struct StudyOptions {
  std::string case_file, output, degrees;
  bool quiet = false;
  workflows::StudyCommandOptions run;
};

void run_study(StudyOptions options) {
  const io::Progress progress("study", options.quiet);
  if (options.run.levels < 1 || options.run.levels > 8)  // before any file is touched
    throw nurbs::InputError("--levels " + std::to_string(options.run.levels) +
                            ": give 1 to 8 levels");
  const std::vector<std::string> outputs = workflows::study_output_files();
  const std::filesystem::path out_dir = output_folder(options.output, {options.case_file}, outputs);
  options.run.limits = solve_limits(0);
  if (!options.degrees.empty())
    for (double p : parse_number_list(options.degrees, "--degrees")) {
      if (p != std::floor(p) || p < 1 || p > 10)
        throw nurbs::InputError("--degrees: " + std::to_string(p) + " is not a degree 1..10");
      options.run.degrees.push_back(static_cast<int>(p));
    }
  workflows::StudyCommandResult result;
  if (io::is_immersed_case(io::parse_json_text(io::read_text_file(options.case_file, "case file"),
                                               options.case_file, "case file"))) {
    const io::ImmersedCase c = io::read_immersed_case(options.case_file);
    io::check_outputs_spare_inputs(input_files(options.case_file), in_folder(out_dir, outputs));
    result = workflows::run_study_immersed(c, options.run, progress);
  } else {
    const io::Case c = io::read_case_file(options.case_file, options.run.limits);
    io::check_outputs_spare_inputs(case_inputs(c), in_folder(out_dir, outputs));
    result = workflows::run_study(c, options.run, progress);
  }
  workflows::write_study_outputs(out_dir, result, progress);
  progress("wrote " + (out_dir / "report.json").string() + ", report.md, study.csv");
}

void setup_study(CLI::App& app) {
  auto options = std::make_shared<StudyOptions>();
  CLI::App* cmd = app.add_subcommand(
      "study", "Refinement study of a case: errors, observed convergence rates and timings");
  cmd->footer(
      "Level l has the case's elements x 2^l per direction, at each degree (k-refinement);\n"
      "on an immersed case the background grid's cells x 2^l, the part immersed again.\n"
      "Errors: relative L2 and energy norms against the case's \"analytic\" solution. A scalar\n"
      "(--quantity) is followed at every level; with 3+ levels the last three give a Richardson\n"
      "extrapolation q* = q3 + (q3 - q2) / (2^r - 1) with observed order\n"
      "r = log2((q2 - q1) / (q3 - q2)) (report.json: degrees[].richardson). Without an analytic\n"
      "solution the error of each level is |q - q*| / |q*| (against the finest level when the\n"
      "last three are not monotone). Rates are fitted over the last three levels.\n"
      "Writes OUTDIR/report.json, report.md, study.csv and convergence.png (gnuplot).");
  cmd->add_option("CASE", options->case_file, "Case file (.json)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", options->output, "Output folder")->required();
  cmd->add_option("--levels", options->run.levels, "Refinement levels (default 4)");
  cmd->add_option("--degrees", options->degrees, "Degrees, e.g. 2,3,4 (default: the case's)");
  cmd->add_option("--load-case", options->run.load_case, "Load case id (default: the first)");
  cmd->add_option("--quantity", options->run.quantity,
                  "Scalar followed and Richardson-extrapolated: strain_energy (default; converges "
                  "monotonically at 2p), max_displacement (max |u| over the control points: "
                  "O(h^2) at best), displacement (at --point)");
  cmd->add_option("--point", options->run.point,
                  "PATCH:U,V[,W] parametric point of --quantity displacement, e.g. 0:1,0.5");
  cmd->add_option("--component", options->run.component,
                  "x, y, z or magnitude (default) of --quantity displacement");
  cmd->add_flag("-q,--quiet", options->quiet, "No progress lines on stderr");
  cmd->callback([options] { run_study(*options); });
}

}  // namespace
ISOSPRING_REGISTER_COMMAND(45, setup_study);
}  // namespace isospring::apps
