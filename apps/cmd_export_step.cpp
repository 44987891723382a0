// `isospring export-step patches.json -o OUT.step`: patches as B-spline faces in STEP or IGES.
// The work is workflows::run_export_step and workflows::export_step_report
// (isospring/workflows/export_step_command.hpp).
#include <iostream>
#include <memory>

#include "cli_util.hpp"
#include "command.hpp"
#include "file_report.hpp"
#include "isospring/workflows/export_step_command.hpp"
#include "isospring/workflows/immersed_refusals.hpp"

namespace isospring::apps {
namespace {

struct ExportStepOptions {
  workflows::ExportStepCommandOptions run;
  bool quiet = false;
};

void run_export_step(const ExportStepOptions& options) {
  workflows::refuse_immersed_case(options.run.input, "export-step");
  check_output_file(options.run.output, input_files(options.run.input));
  const workflows::ExportStepCommandResult r = workflows::run_export_step(options.run);
  FileReport report("export-step", options.run.input, options.run.output);
  workflows::export_step_report(r, options.run, report.json, report.markdown);
  report.write();
  for (const auto& note : r.written.notes) std::cerr << "[export-step] warning: " << note << "\n";
  if (!options.quiet) std::cout << workflows::export_step_summary(r, options.run) << "\n";
}

void setup_export_step(CLI::App& app) {
  auto options = std::make_shared<ExportStepOptions>();
  CLI::App* cmd = app.add_subcommand(
      "export-step", "Write patches as B-spline faces to STEP (.step/.stp) or IGES (.iges/.igs)");
  cmd->add_option("IN", options->run.input, "Patch file, case file or CAD file")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", options->run.output, "Output .step/.stp/.iges/.igs file")
      ->required();
  cmd->add_flag("-q,--quiet", options->quiet, "Do not print the \"wrote ...\" line");
  cmd->footer(
      "Volumes are written as closed solids (their six boundary faces sewn, outward normals), "
      "so `import OUT --solids 0` reads them back as volumes; units: m. Also writes "
      "<OUT>.report.json and <OUT>.report.md beside the output (e.g. fine.step.report.json).");
  cmd->callback([options] { run_export_step(*options); });
}

}  // namespace
ISOSPRING_REGISTER_COMMAND(85, setup_export_step);
}  // namespace isospring::apps
