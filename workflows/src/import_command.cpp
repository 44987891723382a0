// run_import and its report (see import_command.hpp).
#include "isospring/workflows/import_command.hpp"

#include <algorithm>

#include "isospring/geometry/cad_triangulation.hpp"
#include "isospring/geometry/construction.hpp"
#include "isospring/geometry/immersed_cad.hpp"
#include "isospring/geometry/measure.hpp"
#include "isospring/io/immersed_case.hpp"
#include "isospring/io/report_patch.hpp"
#include "isospring/io/vtk_triangulation.hpp"
#include "isospring/workflows/import_immersed.hpp"

namespace isospring::workflows {
// The use cases read and write io's formats; io's names are used unqualified here.
using namespace isospring::io;

ImportCommandResult run_import(const ImportCommandOptions& options, std::ostream* report,
                               std::ostream* log) {
  ImportCommandResult r;
  r.model = geometry::read_cad(options.input);
  const geometry::CadModel& model = r.model;
  if (options.print_report && report) *report << geometry::describe(model);
  if (!options.display.empty()) {
    const auto mesh = geometry::triangulate_cad(options.input, options.deflection);
    write_triangulation_vtp(options.display, mesh);
    r.display_triangles = mesh.triangles.size();
    if (log)
      *log << "wrote " << options.display << ": " << mesh.triangles.size() << " triangles of "
           << model.faces << " faces\n";
  }
  const ImportPath path = choose_import_path(model, options);
  r.path = path.immersed ? "immersed" : "body-fitted";
  r.path_reason = path.reason;
  if (!path.immersed) {
    r.patches = options.solids.empty()
                    ? geometry::cad_patches(model, options.thickness, options.faces)
                    : geometry::cad_solid_patches(model, options.solids);
    return r;
  }
  // The solid is read as analyze will read it (open or invalid shells are refused here, with
  // the fix), its faces described for the user, and the case checked by analyze's own reader
  // before anything is written.
  const geometry::CadSolid solid =
      geometry::read_cad_solid(options.input, model.solids > 1 ? path.solid : -1);
  r.immersed_solid = path.solid;
  r.immersed_volume = geometry::measure_solid(solid).volume;
  r.principal = geometry::principal_frame(solid);
  r.faces = geometry::solid_faces(solid);
  const std::string output = options.output.empty() ? "immersed.json" : options.output;
  r.immersed_case =
      immersed_case_skeleton(options.input, output, path.solid, model.solids, r.faces);
  const std::filesystem::path anchor = std::filesystem::absolute(output);
  // "file" is relative to the output's folder, as analyze will resolve it.
  build_immersed_case(nlohmann::json::parse(r.immersed_case.dump()), anchor);
  return r;
}

// <stem>.report.json / .md beside the patch file: what the part held, what became patches, and
// for every face and solid that did not, why (the same notes `--report` prints).
void import_report(const ImportCommandResult& r, const ImportCommandOptions& options,
                   const std::string& output, nlohmann::json& j, MarkdownReport& md) {
  const geometry::CadModel& model = r.model;
  const std::vector<nurbs::Patch>& patches = r.patches;
  const size_t display_triangles = r.display_triangles;
  j["file_unit"] = model.file_unit;
  j["counts"] = {{"solids", model.solids},
                 {"shells", model.shells},
                 {"faces", model.faces},
                 {"edges", model.edges}};
  j["bounding_box"] = {{model.bbox_min.x(), model.bbox_min.y(), model.bbox_min.z()},
                       {model.bbox_max.x(), model.bbox_max.y(), model.bbox_max.z()}};
  j["cad_volume"] = model.volume;
  j["cad_area"] = model.area;
  j["warnings"] = model.warnings;
  j["options"] = {{"faces", options.faces},
                  {"solids", options.solids},
                  {"thickness", options.thickness},
                  {"path", options.path}};
  j["path"] = r.path;
  j["path_reason"] = r.path_reason;
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
                         format_number(f.area), kind, f.note.empty() ? "-" : f.note});
  }
  for (size_t s = 0; s < model.solid_notes.size(); ++s)
    j["solids"].push_back(
        {{"index", s},
         {"volume_patches",
          std::count(model.patch_solid.begin(), model.patch_solid.end(), static_cast<int>(s))},
         {"note", model.solid_notes[s]},
         {"remark", model.solid_remarks[s]}});
  if (r.path == "immersed") {
    immersed_import_report(r, options, output, j, md);
    return;
  }
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
        {std::to_string(p), format_number(range.min), format_number(range.max)});
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

  md.heading(1, "isospring import: " + options.input);
  md.paragraph("Path: body-fitted (" + r.path_reason + ").");
  md.paragraph("File unit " + model.file_unit + " (written in m). " + std::to_string(model.solids) +
               " solids, " + std::to_string(model.faces) + " faces, " +
               std::to_string(model.edges) + " edges. " + std::to_string(patches.size()) +
               " NURBS patches written to " + output + "; their " +
               (patches.empty() || patches[0].param_dim() < 3 ? "area" : "volume") + " " +
               format_number(measure) + " (CAD: volume " + format_number(model.volume) +
               " m^3, area " + format_number(model.area) + " m^2).");
  if (cad_measure > 0.0)
    md.paragraph(std::string("Check against OpenCascade (BRepGProp): ") +
                 (volumes ? "volume " : "area ") + format_number(measure) + " vs " +
                 format_number(cad_measure) + ", relative difference " +
                 format_number((measure - cad_measure) / cad_measure) + ".");
  md.heading(2, "Patches");
  md.table(patch_table_header(), patch_table_rows(patches));
  md.heading(2, "Jacobian bounds (sampled, 4 Gauss points per element and direction)");
  md.table({"patch", "min", "max"}, jacobian_rows);
  md.heading(2, "Faces");
  md.table({"face", "surface", "edges", "area [m^2]", "conversion", "note"}, face_rows);
  std::vector<std::string> solid_lines;
  for (size_t s = 0; s < model.solid_notes.size(); ++s)
    solid_lines.push_back("solid " + std::to_string(s) + ": " +
                          (model.solid_notes[s].empty() ? "volume patches" : model.solid_notes[s]) +
                          (model.solid_remarks[s].empty() ? "" : "; " + model.solid_remarks[s]));
  if (!solid_lines.empty()) {
    md.heading(2, "Solids");
    md.bullets(solid_lines);
  }
}

}  // namespace isospring::workflows
