// `isospring export-step patches.json -o OUT.step`: patches as B-spline faces in STEP or IGES.
#include <iostream>
#include <memory>

#include "cli_util.hpp"
#include "command.hpp"
#include "file_report.hpp"
#include "isospring/geometry/cad.hpp"

namespace isospring::apps {
namespace {

struct ExportStepOptions {
  std::string input, output;
  bool quiet = false;
};

void setup_export_step(CLI::App& app) {
  auto options = std::make_shared<ExportStepOptions>();
  CLI::App* cmd = app.add_subcommand(
      "export-step", "Write patches as B-spline faces to STEP (.step/.stp) or IGES (.iges/.igs)");
  cmd->add_option("IN", options->input, "Patch file, case file or CAD file")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", options->output, "Output .step/.stp/.iges/.igs file")->required();
  cmd->add_flag("-q,--quiet", options->quiet, "Do not print the \"wrote ...\" line");
  cmd->footer(
      "Volumes are written as their six boundary faces (outward normals); units: m. Also writes "
      "<stem>.report.json and <stem>.report.md beside the output.");
  cmd->callback([options] {
    check_output_file(options->output, input_files(options->input));
    const auto patches = read_patches_any(options->input);
    geometry::write_cad(options->output, patches);
    const std::filesystem::path output(options->output);
    int faces = 0;
    for (const auto& p : patches) faces += p.param_dim() == 3 ? 6 : 1;
    FileReport report("export-step", options->input, output);
    const std::string ext = output.extension().string();
    report.json["format"] =
        (ext == ".iges" || ext == ".igs" || ext == ".IGES" || ext == ".IGS") ? "iges" : "step";
    report.json["patches"] = patches.size();
    report.json["faces"] = faces;
    report.json["file_bytes"] = std::filesystem::file_size(output);
    report.json["units"] = "m";
    report.markdown.heading(1, "isospring export-step: " + options->input);
    report.markdown.paragraph(std::to_string(patches.size()) + " patches written to " +
                              options->output + " as " + std::to_string(faces) +
                              " B-spline faces (volumes as their six boundary faces), in m; " +
                              std::to_string(std::filesystem::file_size(output)) + " bytes.");
    report.markdown.table(patch_table_header(), patch_table_rows(patches));
    report.write();
    if (!options->quiet)
      std::cout << "wrote " << options->output << ": " << patches.size() << " patches\n";
  });
}

}  // namespace
ISOSPRING_REGISTER_COMMAND(85, setup_export_step);
}  // namespace isospring::apps
