// `isospring import PART.step -o patches.json`: a STEP/IGES part to a patch file (metres).
// The work is workflows::run_import and workflows::import_report
// (isospring/workflows/import_command.hpp).
#include <iostream>
#include <memory>

#include "cli_checks.hpp"
#include "cli_util.hpp"
#include "command.hpp"
#include "file_report.hpp"
#include "isospring/io/atomic_file.hpp"
#include "isospring/io/patch_file.hpp"
#include "isospring/workflows/import_command.hpp"
#include "isospring/workflows/import_immersed.hpp"

namespace isospring::apps {
namespace {

struct ImportOptions {
  std::string output;
  bool quiet = false;
  workflows::ImportCommandOptions run;
};

void run_import(const ImportOptions& options) {
  std::vector<std::filesystem::path> extra;
  if (!options.run.display.empty()) extra.emplace_back(options.run.display);
  check_output_file(options.output, {options.run.input}, extra);
  // --quiet drops the "wrote" lines, not the --report asked for.
  workflows::ImportCommandOptions run = options.run;
  run.output = options.output;
  const workflows::ImportCommandResult r =
      workflows::run_import(run, &std::cout, options.quiet ? nullptr : &std::cout);
  if (r.path == "immersed")
    io::write_file_atomically(options.output, workflows::immersed_case_text(r.immersed_case));
  else
    io::write_patch_file(options.output, r.patches);
  FileReport report("import", options.run.input, options.output);
  workflows::import_report(r, run, options.output, report.json, report.markdown);
  report.write();
  if (!options.quiet && r.path == "immersed")
    std::cout << "wrote " << options.output << ": an immersed case of "
              << (r.immersed_solid >= 0 ? "solid " + std::to_string(r.immersed_solid)
                                        : std::string("the sewn faces"))
              << " of " << options.run.input << " (" << r.faces.size()
              << " faces listed; its support, load and material are placeholders to edit), "
                 "because "
              << r.path_reason << "; then: isospring analyze " << options.output
              << " -o OUTDIR; report " << file_report_path(options.output, ".md").string() << "\n";
  else if (!options.quiet)
    std::cout << "wrote " << options.output << ": " << r.patches.size() << " patches from "
              << options.run.input << " (file unit " << r.model.file_unit
              << ", written in m); report " << file_report_path(options.output, ".md").string()
              << "\n";
}

void setup_import(CLI::App& app) {
  auto options = std::make_shared<ImportOptions>();
  CLI::App* cmd = app.add_subcommand(
      "import", "Convert a STEP/IGES part to a NURBS patch file (coordinates in metres)");
  cmd->add_option("PART", options->run.input, "Input .step/.stp/.iges/.igs file")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", options->output, "Output patch file (JSON)")->required();
  cmd->add_option("--faces", options->run.faces,
                  "Keep only these faces (0-based, as listed by --report or `isospring info`)");
  cmd->add_option("--thickness", options->run.thickness,
                  "Extrude the (planar) faces along their normal by this thickness [m]")
      ->check(kNonNegative);
  cmd->add_option("--solids", options->run.solids,
                  "Keep only these solids as volumes (0-based, as listed by `isospring info`)")
      ->excludes("--faces")
      ->excludes("--thickness");
  cmd->add_option("--display", options->run.display,
                  "Also write a triangulation of every face (trimmed ones too) as VTK .vtp, cell "
                  "data `face`, for ParaView; written even when some faces are not usable");
  cmd->add_option("--deflection", options->run.deflection,
                  "Display triangulation: largest distance to the faces, as a fraction of the "
                  "part's bounding-box diagonal (default 1e-3)")
      ->check(CLI::Range(1e-6, 0.5));
  cmd->add_option("--path", options->run.path,
                  "auto (default): body-fitted volume patches where the part allows them, else an "
                  "immersed case of the solid; body-fitted: patches only; immersed: an immersed "
                  "case even when volumes exist")
      ->check(CLI::IsMember({"auto", "body-fitted", "immersed"}));
  cmd->add_flag("--report", options->run.print_report, "Print the per-face report");
  cmd->add_flag("-q,--quiet", options->quiet, "Do not print the \"wrote ...\" line");
  cmd->footer(
      "A solid of hexahedral topology becomes one volume patch (transfinite interpolation of its "
      "faces, or the extrusion of a face for prisms), a full solid of revolution with a 4-sided "
      "profile four exact quarter volumes; otherwise "
      "each untrimmed face becomes a surface patch, a trimmed face with four edges the Coons "
      "patch of its edges when that lies on the face's surface, and a planar face with holes or "
      "other edge counts conforming 4-sided patches (a ring of 4 around each hole, rectangles "
      "elsewhere); a prism of such a face becomes its patches extruded. Other faces are reported "
      "with what to do. A solid that cannot become volume patches takes the immersed path: "
      "OUT.json is then an immersed case file (`isospring analyze` runs it) listing the solid's "
      "faces, with a placeholder support and load to replace; the report says which path the "
      "part took and why.");
  cmd->callback([options] { run_import(*options); });
}

}  // namespace
ISOSPRING_REGISTER_COMMAND(15, setup_import);
}  // namespace isospring::apps
