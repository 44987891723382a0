// `isospring export MODEL.json -o OUT [--format json|mjcf|sofa|vtk|reduced]`: a calibrated spring
// model (model.json) for real-time engines and viewers: MuJoCo MJCF, a SOFA scene, VTK poly data,
// a validated, normalised model.json, or its reduced model for haptic rates.
// The work is workflows::run_export and workflows::export_report
// (isospring/workflows/export_command.hpp).
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "cli_util.hpp"
#include "command.hpp"
#include "file_report.hpp"
#include "isospring/workflows/export_command.hpp"
#include "isospring/workflows/export_formats.hpp"

namespace isospring::apps {
namespace {

struct ExportOptions {
  bool quiet = false;
  workflows::ExportCommandOptions run;
};

void run_export(const ExportOptions& options) {
  check_output_file(options.run.output, {options.run.input});
  const workflows::ExportCommandResult r = workflows::run_export(options.run);
  FileReport report("export", options.run.input, options.run.output);
  workflows::export_report(r, options.run, report.json, report.markdown);
  report.write();
  if (!options.quiet)
    std::cerr << "[export] wrote " << options.run.output << " (" << r.format
              << "): " << r.model.network.positions.size() << " particles, "
              << r.model.network.springs.size() << " springs\n";
}

void setup_export(CLI::App& app) {
  auto options = std::make_shared<ExportOptions>();
  CLI::App* cmd = app.add_subcommand(
      "export", "Export a calibrated spring model (model.json) to MuJoCo, SOFA, VTK or JSON");
  cmd->add_option("MODEL", options->run.input, "Spring model written by `isospring calibrate`")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", options->run.output, "Output file")->required();
  // The formats, their help and the check all come from workflows::export_formats().
  std::vector<std::string> format_names;
  for (const workflows::ExportFormat& format : workflows::export_formats())
    format_names.push_back(format.name);
  cmd->add_option("--format", options->run.format, workflows::export_formats_help())
      ->check(CLI::IsMember(format_names));
  cmd->add_option("--gravity", options->run.gravity,
                  "Gravity gx,gy,gz [m/s^2] for mjcf and sofa; default: the model's gravity, else "
                  "0,0,-9.81 (3D) or 0,-9.81,0 (a flat 2D model moves in x-y only)");
  cmd->add_option("--timestep", options->run.timestep,
                  "Time step [s]: mjcf and sofa, 0 = 0.2 x the explicit stability limit; reduced, "
                  "0 = 1e-3 (1 kHz)");
  cmd->add_option("--modes", options->run.modes,
                  "reduced: lowest natural modes in the basis (the model's load cases and gravity "
                  "join it as static shapes)")
      ->check(CLI::Range(1, 100000));
  cmd->add_flag("--corotated", options->run.corotated,
                "reduced: the corotated model for large rotations (modal derivatives join the "
                "basis; O(n r) per step; docs/reduced_model.md)");
  cmd->add_flag("-q,--quiet", options->quiet, "No progress line on stderr");
  cmd->footer(
      "mjcf: free particles are bodies with slide joints, fixed ones sites in the world, springs\n"
      "spatial tendons (stiffness, damping, springlength = L0); contacts off.\n"
      "sofa: MechanicalObject + UniformMass/DiagonalMass + StiffSpringForceField + "
      "FixedConstraint.\n"
      "vtk: particles and springs with mass, fixed, stiffness, damping, rest_length, group.\n"
      "reduced: basis, eigenvalues, reduced damping and step matrix; the error against the full\n"
      "network per load goes into the report (docs/reduced_model.md).");
  cmd->callback([options] { run_export(*options); });
}

}  // namespace
ISOSPRING_REGISTER_COMMAND(80, setup_export);

}  // namespace isospring::apps
