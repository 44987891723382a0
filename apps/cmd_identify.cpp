// `isospring identify CASE.json -o OUTDIR [--drop-outside] [--quiet]`: the measured-data loop.
// Fits the case's model to the markers of `"measurements"`, adds the effects the residual calls
// for (fitting/identify.hpp), recalibrates the spring model against the corrected reference
// (fitting/identify_recalibration.hpp) and writes OUTDIR/report.json, report.md, model.json (with
// the carried gravity and load cases), markers_*.vtp (measured, model and residual per load case,
// before and after), residuals.svg (our own SVG: one row per load case) and
// errors_before_after.png (gnuplot, when present). The work is workflows::run_identify and
// workflows::write_identify_outputs (isospring/workflows/identify_command.hpp); this file parses
// the flags.
#include <memory>
#include <optional>

#include "cli_util.hpp"
#include "command.hpp"
#include "isospring/io/atomic_file.hpp"
#include "isospring/io/case_file.hpp"
#include "isospring/io/immersed_case.hpp"
#include "isospring/io/json_text.hpp"
#include "isospring/io/output_guard.hpp"
#include "isospring/io/report.hpp"
#include "isospring/workflows/identify_command.hpp"
#include "isospring/workflows/identify_immersed_command.hpp"

namespace isospring::apps {
namespace {

struct IdentifyFlags {
  std::string case_file;
  std::string output;
  bool quiet = false;
  workflows::IdentifyCommandOptions options;
  std::optional<long> max_dofs;
  bool no_discretization_check = false;
};

// An immersed case: the part in its background grid (workflows::run_identify_immersed).
void run_immersed(const IdentifyFlags& flags, const io::Progress& progress) {
  const std::filesystem::path out_dir =
      output_folder(flags.output, {flags.case_file}, workflows::identify_output_files());
  progress("reading " + flags.case_file);
  const io::ImmersedCase c = io::read_immersed_case(flags.case_file);
  std::vector<std::string> ids;
  for (const auto& load : c.load_cases) ids.push_back(load.id);
  io::check_outputs_spare_inputs(input_files(flags.case_file),
                                 in_folder(out_dir, workflows::identify_output_files(ids)));
  const workflows::IdentifyCommandResult r =
      workflows::run_identify_immersed(c, flags.options, progress);
  workflows::write_identify_outputs(out_dir, r, progress);
  progress("rms " + io::format_number(r.identify.before.rms, 3) + " m -> " +
           io::format_number(r.identify.after.rms, 3) + " m; wrote " +
           (out_dir / "report.json").string());
}

void run(IdentifyFlags flags) {
  const io::Progress progress("identify", flags.quiet);
  flags.options.max_dofs = flags.max_dofs;
  flags.options.discretization_check = !flags.no_discretization_check;
  if (io::is_immersed_case(io::parse_json_text(io::read_text_file(flags.case_file, "case file"),
                                               flags.case_file, "case file")))
    return run_immersed(flags, progress);
  const std::filesystem::path out_dir =
      output_folder(flags.output, {flags.case_file}, workflows::identify_output_files());
  progress("reading " + flags.case_file);
  const io::Case c = io::read_case_file(flags.case_file, solve_limits(0));
  std::vector<std::string> ids;
  for (const auto& load : c.problem.load_cases) ids.push_back(load.id);
  io::check_outputs_spare_inputs(case_inputs(c),
                                 in_folder(out_dir, workflows::identify_output_files(ids)));
  const workflows::IdentifyCommandResult r = workflows::run_identify(c, flags.options, progress);
  workflows::write_identify_outputs(out_dir, r, progress);
  progress("rms " + io::format_number(r.identify.before.rms, 3) + " m -> " +
           io::format_number(r.identify.after.rms, 3) + " m; wrote " +
           (out_dir / "report.json").string());
}

void setup_identify(CLI::App& app) {
  auto options = std::make_shared<IdentifyFlags>();
  CLI::App* cmd = app.add_subcommand(
      "identify", "Fit the model to measured marker displacements and add missing effects");
  cmd->footer(
      "The case file's \"measurements\" object names the marker CSV (header\n"
      "load_case,x,y,z,ux,uy,uz[,sigma] by default; columns and units can be mapped).\n"
      "Fits E (and nu with fit_poisson), then adds effects (gravity, support_compliance,\n"
      "stiffness_gradient, rigid_offset, load_scale, geometric_nonlinearity,\n"
      "rigid_offset_per_load) while an F-test\n"
      "finds them significant (docs/identify.md). Before that, the reference is refined\n"
      "(degree, then elements) until its error at the markers is below a third of the\n"
      "noise, within --max-dofs; beyond the budget the F-tests are widened instead.\n"
      "Recalibrates the spring model against the corrected reference (identified material,\n"
      "gravity, load factors, stiffness gradient; the case's \"calibration\" object applies).\n"
      "Writes OUTDIR/report.json, report.md, model.json, residuals.svg/.csv,\n"
      "markers_<case>_*.vtp. Immersed cases (geometry type \"immersed\") run the same loop\n"
      "with the effects that have an immersed form (docs/immersed.md), without the\n"
      "recalibration; their discretisation check refines the background grid (cells\n"
      "x sqrt 2 per level), re-immersing the part each time.");
  cmd->add_option("CASE", options->case_file, "Case file (.json) with \"measurements\"")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", options->output, "Output folder (created if missing)")->required();
  cmd->add_flag("--drop-outside", options->options.drop_outside,
                "Leave out markers off the model (listed in the report) instead of failing");
  cmd->add_option("--max-dofs", options->max_dofs,
                  "DOF budget of the discretisation check (default: measurements.max_dofs, "
                  "else 25000)")
      ->check(CLI::Range(1L, 1000000000L));
  cmd->add_flag("--no-discretization-check", options->no_discretization_check,
                "Run the loop on the case's discretisation without checking its error against "
                "the noise");
  cmd->add_flag("-q,--quiet", options->quiet, "No progress lines");
  cmd->callback([options] { run(*options); });
}

}  // namespace
ISOSPRING_REGISTER_COMMAND(60, setup_identify);
}  // namespace isospring::apps
