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
      "Volumes are written as closed solids (their six boundary faces sewn, outward normals), "
      "so `import OUT --solids 0` reads them back as volumes; units: m. Also writes "
      "<OUT>.report.json and <OUT>.report.md beside the output (e.g. fine.step.report.json).");
  cmd->callback([options] {
    check_output_file(options->output, input_files(options->input));
    const auto patches = read_patches_any(options->input);
    const geometry::CadWriteSummary written = geometry::write_cad(options->output, patches);
    const std::filesystem::path output(options->output);
    FileReport report("export-step", options->input, output);
    const std::string ext = output.extension().string();
    report.json["format"] =
        (ext == ".iges" || ext == ".igs" || ext == ".IGES" || ext == ".IGS") ? "iges" : "step";
    report.json["patches"] = patches.size();
    report.json["faces"] = written.faces;
    report.json["solids"] = written.solids;
    report.json["warnings"] = written.notes;
    report.json["file_bytes"] = std::filesystem::file_size(output);
    report.json["units"] = "m";
    report.markdown.heading(1, "isospring export-step: " + options->input);
    report.markdown.paragraph(std::to_string(patches.size()) + " patches written to " +
                              options->output + " as " + std::to_string(written.faces) +
                              " B-spline faces, " + std::to_string(written.solids) +
                              " closed solid(s) (every volume patch as its six sides sewn), in "
                              "m; " +
                              std::to_string(std::filesystem::file_size(output)) + " bytes.");
    if (!written.notes.empty()) {
      std::vector<std::string> items;
      for (const auto& note : written.notes) items.push_back("Warning: " + note);
      report.markdown.bullets(items);
    }
    report.markdown.table(patch_table_header(), patch_table_rows(patches));
    report.write();
    for (const auto& note : written.notes) std::cerr << "[export-step] warning: " << note << "\n";
    if (!options->quiet)
      std::cout << "wrote " << options->output << ": " << patches.size() << " patches ("
                << written.solids << " solid(s))\n";
  });
}

}  // namespace
ISOSPRING_REGISTER_COMMAND(85, setup_export_step);
}  // namespace isospring::apps
