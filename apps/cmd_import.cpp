// `isospring import PART.step -o patches.json`: a STEP/IGES part to a patch file (metres).
#include <algorithm>
#include <iostream>
#include <memory>

#include "cli_checks.hpp"
#include "cli_util.hpp"
#include "command.hpp"
#include "file_report.hpp"
#include "isospring/geometry/cad.hpp"
#include "isospring/geometry/cad_triangulation.hpp"
#include "isospring/geometry/construction.hpp"
#include "isospring/geometry/measure.hpp"
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

// <stem>.report.json / .md beside the patch file: what the part held, what became patches, and
// for every face and solid that did not, why (the same notes `--report` prints).
void write_import_report(const ImportOptions& options, const geometry::CadModel& model,
                         const std::vector<nurbs::Patch>& patches, size_t display_triangles) {
  FileReport report("import", options.input, options.output);
  nlohmann::json& j = report.json;
  j["file_unit"] = model.file_unit;
  j["counts"] = {{"solids", model.solids},
                 {"shells", model.shells},
                 {"faces", model.faces},
                 {"edges", model.edges}};
  j["bounding_box"] = {{model.bbox_min.x(), model.bbox_min.y(), model.bbox_min.z()},
                       {model.bbox_max.x(), model.bbox_max.y(), model.bbox_max.z()}};
  j["cad_volume"] = model.volume;
  j["cad_area"] = model.area;
  j["options"] = {
      {"faces", options.faces}, {"solids", options.solids}, {"thickness", options.thickness}};
  std::vector<std::vector<std::string>> face_rows;
  for (const auto& f : model.face_reports) {
    const std::string kind =
        f.natural ? "natural"
                  : (f.coons ? "coons"
                             : (f.split > 0 ? "split into " + std::to_string(f.split) + " patches"
                                            : "not usable"));
    j["faces"].push_back({{"index", f.index},
                          {"surface_type", f.surface_type},
                          {"wires", f.wires},
                          {"edges", f.edges},
                          {"area", f.area},
                          {"conversion", kind},
                          {"coons_deviation", f.coons_deviation},
                          {"split_patches", f.split},
                          {"jacobian_min", f.jacobian_min},
                          {"jacobian_max", f.jacobian_max},
                          {"note", f.note}});
    face_rows.push_back({std::to_string(f.index), f.surface_type, std::to_string(f.edges),
                         io::format_number(f.area), kind, f.note.empty() ? "-" : f.note});
  }
  for (size_t s = 0; s < model.solid_notes.size(); ++s)
    j["solids"].push_back(
        {{"index", s},
         {"volume_patches",
          std::count(model.patch_solid.begin(), model.patch_solid.end(), static_cast<int>(s))},
         {"note", model.solid_notes[s]}});
  j["patch_count"] = patches.size();
  std::vector<std::vector<std::string>> jacobian_rows;
  for (size_t p = 0; p < patches.size(); ++p) {
    nlohmann::json pj = patch_json(patches[p]);
    // Sampled at 4 Gauss points per element and direction; for surfaces in 3D the norm of
    // dX/du x dX/dv (the sign was checked in the face's plane when it was cut).
    const geometry::JacobianRange range = geometry::jacobian_range(patches[p], 4);
    pj["jacobian_min"] = range.min;
    pj["jacobian_max"] = range.max;
    j["patches"].push_back(pj);
    jacobian_rows.push_back(
        {std::to_string(p), io::format_number(range.min), io::format_number(range.max)});
  }
  const double measure = patches.empty() ? 0.0 : geometry::measure(patches);
  j["patches_measure"] = measure;
  // What OpenCascade says the same thing measures: the solids' volume for volume patches, the
  // chosen faces' area for surface patches (unless extruded by a thickness).
  const bool volumes = !patches.empty() && patches[0].param_dim() == 3;
  double cad_measure = 0.0;
  if (volumes && options.thickness == 0.0) {
    cad_measure = model.volume;
  } else if (!volumes) {
    for (const auto& f : model.face_reports)
      if (options.faces.empty() ||
          std::find(options.faces.begin(), options.faces.end(), f.index) != options.faces.end())
        cad_measure += f.area;
  }
  if (cad_measure > 0.0) {
    j["cad_measure"] = cad_measure;
    j["measure_relative_error"] = (measure - cad_measure) / cad_measure;
  }
  if (!options.display.empty())
    j["display"] = {{"file", options.display}, {"triangles", display_triangles}};

  io::MarkdownReport& md = report.markdown;
  md.heading(1, "isospring import: " + options.input);
  md.paragraph("File unit " + model.file_unit + " (written in m). " + std::to_string(model.solids) +
               " solids, " + std::to_string(model.faces) + " faces, " +
               std::to_string(model.edges) + " edges. " + std::to_string(patches.size()) +
               " NURBS patches written to " + options.output + "; their " +
               (patches.empty() || patches[0].param_dim() < 3 ? "area" : "volume") + " " +
               io::format_number(measure) + " (CAD: volume " + io::format_number(model.volume) +
               " m^3, area " + io::format_number(model.area) + " m^2).");
  if (cad_measure > 0.0)
    md.paragraph(std::string("Check against OpenCascade (BRepGProp): ") +
                 (volumes ? "volume " : "area ") + io::format_number(measure) + " vs " +
                 io::format_number(cad_measure) + ", relative difference " +
                 io::format_number((measure - cad_measure) / cad_measure) + ".");
  md.heading(2, "Patches");
  md.table(patch_table_header(), patch_table_rows(patches));
  md.heading(2, "Jacobian bounds (sampled, 4 Gauss points per element and direction)");
  md.table({"patch", "min", "max"}, jacobian_rows);
  md.heading(2, "Faces");
  md.table({"face", "surface", "edges", "area [m^2]", "conversion", "note"}, face_rows);
  std::vector<std::string> solid_lines;
  for (size_t s = 0; s < model.solid_notes.size(); ++s)
    solid_lines.push_back("solid " + std::to_string(s) + ": " +
                          (model.solid_notes[s].empty() ? "volume patches" : model.solid_notes[s]));
  if (!solid_lines.empty()) {
    md.heading(2, "Solids");
    md.bullets(solid_lines);
  }
  report.write();
}

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
      ->check(kNonNegative);
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
      "each untrimmed face becomes a surface patch, a trimmed face with four edges the Coons "
      "patch of its edges when that lies on the face's surface, and a planar face with holes or "
      "other edge counts conforming 4-sided patches (a ring of 4 around each hole, rectangles "
      "elsewhere); a prism of such a face becomes its patches extruded. Other faces are reported "
      "with what to do.");
  cmd->callback([options] {
    std::vector<std::filesystem::path> extra;
    if (!options->display.empty()) extra.emplace_back(options->display);
    check_output_file(options->output, {options->input}, extra);
    const geometry::CadModel model = geometry::read_cad(options->input);
    if (options->report) std::cout << geometry::describe(model);
    size_t display_triangles = 0;
    if (!options->display.empty()) {
      const auto mesh = geometry::triangulate_cad(options->input, options->deflection);
      io::write_triangulation_vtp(options->display, mesh);
      display_triangles = mesh.triangles.size();
      if (!options->quiet)
        std::cout << "wrote " << options->display << ": " << mesh.triangles.size()
                  << " triangles of " << model.faces << " faces\n";
    }
    const auto patches = options->solids.empty()
                             ? geometry::cad_patches(model, options->thickness, options->faces)
                             : geometry::cad_solid_patches(model, options->solids);
    io::write_patch_file(options->output, patches);
    write_import_report(*options, model, patches, display_triangles);
    if (!options->quiet)
      std::cout << "wrote " << options->output << ": " << patches.size() << " patches from "
                << options->input << " (file unit " << model.file_unit << ", written in m); report "
                << file_report_path(options->output, ".md").string() << "\n";
  });
}

}  // namespace
ISOSPRING_REGISTER_COMMAND(15, setup_import);
}  // namespace isospring::apps
