// `isospring export-step patches.json -o OUT.step`: patches as B-spline faces in STEP or IGES.
#include <iostream>
#include <memory>

#include "cli_util.hpp"
#include "command.hpp"
#include "isospring/geometry/cad.hpp"

namespace isospring::apps {
namespace {

struct ExportStepOptions {
  std::string input, output;
};

void setup_export_step(CLI::App& app) {
  auto options = std::make_shared<ExportStepOptions>();
  CLI::App* cmd = app.add_subcommand(
      "export-step", "Write patches as B-spline faces to STEP (.step/.stp) or IGES (.iges/.igs)");
  cmd->add_option("IN", options->input, "Patch file, case file or CAD file")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", options->output, "Output .step/.stp/.iges/.igs file")->required();
  cmd->footer("Volumes are written as their six boundary faces (outward normals); units: m.");
  cmd->callback([options] {
    const auto patches = read_patches_any(options->input);
    geometry::write_cad(options->output, patches);
    std::cout << "wrote " << options->output << ": " << patches.size() << " patches\n";
  });
}

}  // namespace
ISOSPRING_REGISTER_COMMAND(85, setup_export_step);
}  // namespace isospring::apps
