// `isospring export-calculix CASE.json -o deck.inp`: the case's problem as a CalculiX input
// deck (20-node hexahedra or, in 2D, 8-node quadrilaterals on the exact geometry), for an
// independent check with `ccx -i deck`. The work is workflows::run_export_calculix and
// workflows::export_calculix_report (isospring/workflows/export_calculix_command.hpp).
#include <memory>

#include "cli_util.hpp"
#include "command.hpp"
#include "file_report.hpp"
#include "isospring/io/case_file.hpp"
#include "isospring/io/report.hpp"
#include "isospring/workflows/export_calculix_command.hpp"
#include "isospring/workflows/immersed_refusals.hpp"

namespace isospring::apps {
namespace {

struct ExportCalculixOptions {
  workflows::ExportCalculixCommandOptions run;
  bool quiet = false;
};

void run_export_calculix(const ExportCalculixOptions& options) {
  const io::Progress progress("export-calculix", options.quiet);
  // Both output checks before the case is read: a bad deck name costs no work.
  workflows::refuse_immersed_case(options.run.case_file, "export-calculix");
  workflows::check_calculix_output(options.run.output);
  check_output_file(options.run.output, input_files(options.run.case_file));
  const workflows::ExportCalculixCommandResult r =
      workflows::run_export_calculix(io::read_case_file(options.run.case_file), options.run);
  FileReport report("export-calculix", options.run.case_file, options.run.output);
  workflows::export_calculix_report(r, options.run, report.json, report.markdown);
  report.write();
  progress(workflows::export_calculix_summary(r, options.run));
}

void setup_export_calculix(CLI::App& app) {
  auto options = std::make_shared<ExportCalculixOptions>();
  CLI::App* cmd = app.add_subcommand(
      "export-calculix",
      "Write a case as a CalculiX deck (20-node hexahedra, 8-node quads in 2D) for cross-checks");
  cmd->footer(
      "One element per knot span of the discretised patches; nodes are exact NURBS points at\n"
      "element corners and mid-edges. Supports become *BOUNDARY, tractions and pressures\n"
      "consistent nodal forces (*CLOAD), body force and gravity *DLOAD; one *STEP per load case\n"
      "printing U for all nodes. Point loads and single-control-point supports have no nodes and\n"
      "are rejected. Run: ccx -i DECK (without .inp); displacements are in DECK.dat.");
  cmd->add_option("CASE", options->run.case_file, "Case file (.json)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", options->run.output, "Deck to write (.inp)")->required();
  cmd->add_option("--element", options->run.element,
                  "3D: C3D20R (reduced integration, default: no locking in bending) or C3D20; "
                  "plane stress: CPS8R (default) or CPS8; plane strain: CPE8R (default) or CPE8")
      ->check(CLI::IsMember({"C3D20R", "C3D20", "CPS8R", "CPS8", "CPE8R", "CPE8"}));
  cmd->add_flag("-q,--quiet", options->quiet, "No progress lines on stderr");
  cmd->callback([options] { run_export_calculix(*options); });
}

}  // namespace
ISOSPRING_REGISTER_COMMAND(85, setup_export_calculix);
}  // namespace isospring::apps
