// `isospring import PART.step -o patches.json`: a STEP/IGES part to a patch file (metres).
#include <iostream>
#include <memory>

#include "command.hpp"
#include "isospring/geometry/cad.hpp"
#include "isospring/geometry/cad_triangulation.hpp"
#include "isospring/io/patch_file.hpp"
#include "isospring/io/vtk_triangulation.hpp"

namespace isospring::apps {
namespace {

struct ImportOptions {
  std::string input, output;
  double thickness = 0.0;
  std::vector<int> faces, solids;
  std::string display;
  double deflection = 1e-3;
  bool report = false;
  bool quiet = false;
};

void setup_import(CLI::App& app) {
  auto options = std::make_shared<ImportOptions>();
  CLI::App* cmd = app.add_subcommand(
      "import", "Convert a STEP/IGES part to a NURBS patch file (coordinates in metres)");
  cmd->add_option("PART", options->input, "Input .step/.stp/.iges/.igs file")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", options->output, "Output patch file (JSON)")->required();
  cmd->add_option("--faces", options->faces,
                  "Keep only these faces (0-based, as listed by --report or `isospring info`)");
  cmd->add_option("--thickness", options->thickness,
                  "Extrude the (planar) faces along their normal by this thickness [m]")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--solids", options->solids,
                  "Keep only these solids as volumes (0-based, as listed by `isospring info`)")
      ->excludes("--faces")
      ->excludes("--thickness");
  cmd->add_option("--display", options->display,
                  "Also write a triangulation of every face (trimmed ones too) as VTK .vtp, cell "
                  "data `face`, for ParaView; written even when some faces are not usable");
  cmd->add_option("--deflection", options->deflection,
                  "Display triangulation: largest distance to the faces, as a fraction of the "
                  "part's bounding-box diagonal (default 1e-3)")
      ->check(CLI::Range(1e-6, 0.5));
  cmd->add_flag("--report", options->report, "Print the per-face report");
  cmd->add_flag("-q,--quiet", options->quiet, "Do not print the \"wrote ...\" line");
  cmd->footer(
      "A solid of hexahedral topology becomes one volume patch (transfinite interpolation of its "
      "faces, or the extrusion of a face for prisms), a full solid of revolution with a 4-sided "
      "profile four exact quarter volumes; otherwise "
      "each untrimmed face becomes a surface patch, and a trimmed face with four edges the Coons "
      "patch of its edges when that lies on the face's surface. Other trimmed faces (holes, "
      "non-quadrilateral outlines) are reported with what to do.");
  cmd->callback([options] {
    const geometry::CadModel model = geometry::read_cad(options->input);
    if (options->report) std::cout << geometry::describe(model);
    if (!options->display.empty()) {
      const auto mesh = geometry::triangulate_cad(options->input, options->deflection);
      io::write_triangulation_vtp(options->display, mesh);
      if (!options->quiet)
        std::cout << "wrote " << options->display << ": " << mesh.triangles.size()
                  << " triangles of " << model.faces << " faces\n";
    }
    const auto patches = options->solids.empty()
                             ? geometry::cad_patches(model, options->thickness, options->faces)
                             : geometry::cad_solid_patches(model, options->solids);
    io::write_patch_file(options->output, patches);
    if (!options->quiet)
      std::cout << "wrote " << options->output << ": " << patches.size() << " patches from "
                << options->input << " (file unit " << model.file_unit << ", written in m)\n";
  });
}

}  // namespace
ISOSPRING_REGISTER_COMMAND(15, setup_import);
}  // namespace isospring::apps
