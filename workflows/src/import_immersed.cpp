// The immersed path of `isospring import` (see import_immersed.hpp).
#include "isospring/workflows/import_immersed.hpp"

#include <algorithm>
#include <cmath>

#include "isospring/nurbs/error.hpp"

namespace isospring::workflows {
namespace fs = std::filesystem;
using nurbs::InputError;
namespace {

// Coordinates below 1e-14 m (far below any CAD tolerance) are written as 0: OpenCascade's
// -0 and 1e-35 only distract a reader choosing faces.
double clean(double x) {
  return std::abs(x) < 1e-14 ? 0.0 : x;
}

nlohmann::ordered_json vec(const Eigen::Vector3d& v) {
  return {clean(v.x()), clean(v.y()), clean(v.z())};
}

// The solids `options.solids` chooses (all when empty), checked against the file.
std::vector<int> chosen_solids(const geometry::CadModel& model,
                               const ImportCommandOptions& options) {
  std::vector<int> solids = options.solids;
  if (solids.empty())
    for (int s = 0; s < model.solids; ++s) solids.push_back(s);
  for (int s : solids)
    if (s < 0 || s >= model.solids)
      throw InputError(model.file.string() + ": --solids " + std::to_string(s) +
                       ": not a solid of the part (it has " + std::to_string(model.solids) +
                       "; indices are 0-based, listed by `isospring info`)");
  return solids;
}

// Refuses a choice of several solids for the one immersed solid, naming which to choose.
void require_one_solid(const geometry::CadModel& model, const std::vector<int>& solids,
                       const std::string& why) {
  if (solids.size() == 1) return;
  throw InputError(model.file.string() + ": " + why + "; an immersed case holds one solid and " +
                   std::to_string(solids.size()) +
                   " are chosen: import one at a time with --solids N (0-based, as `isospring "
                   "info` lists them)");
}

// The face the placeholder support clamps: the largest planar face, else the largest face.
int placeholder_clamp(const std::vector<geometry::SolidFace>& faces) {
  const geometry::SolidFace* best = nullptr;
  for (const geometry::SolidFace& f : faces) {
    const bool planar = f.surface_type == "plane";
    const bool best_planar = best && best->surface_type == "plane";
    if (!best || (planar && !best_planar) || (planar == best_planar && f.area > best->area))
      best = &f;
  }
  return best ? best->index : 0;
}

}  // namespace

ImportPath choose_import_path(const geometry::CadModel& model,
                              const ImportCommandOptions& options) {
  const std::string name = model.file.string();
  if (options.path != "auto" && options.path != "body-fitted" && options.path != "immersed")
    throw InputError("--path " + options.path + ": use auto, body-fitted or immersed");
  const bool faces_asked = !options.faces.empty() || options.thickness > 0.0;
  ImportPath path;
  if (options.path == "body-fitted") {
    path.reason = "--path body-fitted: NURBS patches of the part as it is (no immersed case)";
    return path;
  }
  if (options.path == "immersed") {
    if (faces_asked)
      throw InputError(name +
                       ": --path immersed takes a whole solid; drop --faces and --thickness");
    path.immersed = true;
    path.reason =
        "--path immersed: the solid's exact B-rep in a B-spline background grid, as asked";
    if (model.solids == 0) {  // faces only: read_cad_solid sews them, or names the gap
      path.reason += " (the file's faces sewn into one solid)";
      return path;
    }
    const std::vector<int> solids = chosen_solids(model, options);
    require_one_solid(model, solids, "--path immersed");
    path.immersed = true;
    path.solid = solids.front();
    path.reason =
        "--path immersed: the solid's exact B-rep in a B-spline background grid, as asked";
    return path;
  }
  if (faces_asked || model.solids == 0) {
    path.reason = faces_asked ? "--faces or --thickness: patches of the chosen faces"
                              : "the file holds faces only (no solid): patches of its faces";
    return path;
  }
  const std::vector<int> solids = chosen_solids(model, options);
  std::vector<int> refused;
  for (int s : solids)
    if (!model.solid_notes[static_cast<size_t>(s)].empty()) refused.push_back(s);
  if (refused.empty()) {
    path.reason =
        "every solid became body-fitted volume patches (block, prism, solid of "
        "revolution or block with through-holes), the default where it exists";
    return path;
  }
  const int s = refused.front();
  const std::string note = model.solid_notes[static_cast<size_t>(s)];
  require_one_solid(model, solids,
                    "solid " + std::to_string(s) + " cannot become body-fitted volume patches (" +
                        note + ") and takes the immersed path");
  path.immersed = true;
  path.solid = s;
  path.reason = "solid " + std::to_string(s) + " cannot become body-fitted volume patches (" +
                note +
                "), so it is analysed immersed: its exact B-rep in a B-spline background grid, "
                "supports imposed weakly on its faces";
  return path;
}

nlohmann::ordered_json faces_json(const std::vector<geometry::SolidFace>& faces) {
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (const geometry::SolidFace& f : faces) {
    nlohmann::ordered_json j = {{"index", f.index},
                                {"type", f.surface_type},
                                {"area", f.area},
                                {"centroid", vec(f.centroid)},
                                {"box", {vec(f.box_min), vec(f.box_max)}}};
    if (!f.name.empty()) j["name"] = f.name;
    if (f.normal.norm() > 0) j["normal"] = vec(f.normal);
    if (f.axis.norm() > 0) {
      j["axis_point"] = vec(f.axis_point);
      j["axis"] = vec(f.axis);
      j["radius"] = f.radius;
    }
    out.push_back(j);
  }
  return out;
}

nlohmann::ordered_json immersed_case_skeleton(const fs::path& part, const fs::path& output,
                                              int solid, int solids,
                                              const std::vector<geometry::SolidFace>& faces) {
  // Relative to the case's folder, so that the two move together; absolute when the relative
  // path would climb to the file system's root (nothing shared but the root).
  const fs::path folder = fs::absolute(output).lexically_normal().parent_path();
  fs::path file = fs::absolute(part).lexically_normal().lexically_relative(folder);
  const auto climbs = std::count(file.begin(), file.end(), fs::path(".."));
  const fs::path below_root = folder.relative_path();
  const auto depth = std::distance(below_root.begin(), below_root.end());
  if (file.empty() || climbs >= depth) file = fs::absolute(part).lexically_normal();
  const int clamp = placeholder_clamp(faces);
  nlohmann::ordered_json geometry = {
      {"type", "immersed"}, {"file", file.generic_string()}, {"degree", 2}};
  if (solids > 1 && solid >= 0) geometry["solid"] = solid;
  return nlohmann::ordered_json{
      {"schema_version", 1},
      {"name", part.stem().string()},
      {"description",
       "Immersed analysis of " + part.filename().string() +
           ", written by `isospring import`. PLACEHOLDERS to replace: the support (face " +
           std::to_string(clamp) +
           ", the largest planar face, clamped), the load (the part's own weight along -z) and "
           "the material (steel). Choose supports and loads from \"faces\" by index or by a "
           "selector (plane, box, cylinder, STEP name; docs/case-files.md, \"Immersed "
           "geometry\"), then run `isospring analyze` on this file."},
      {"geometry", geometry},
      {"material", {{"E", 2.1e11}, {"nu", 0.3}, {"density", 7850.0}}},
      {"boundary", {{{"face", clamp}, {"fix", {"x", "y", "z"}}}}},
      {"load_cases", {{{"id", "gravity"}, {"gravity", {0.0, 0.0, -9.81}}}}},
      {"faces", faces_json(faces)}};
}

std::string immersed_case_text(const nlohmann::ordered_json& c) {
  std::string text = "{";
  bool first = true;
  for (const auto& [key, value] : c.items()) {
    text += (first ? "\n  " : ",\n  ") + nlohmann::ordered_json(key).dump() + ": ";
    first = false;
    if (key != "faces" || !value.is_array() || value.empty()) {
      text += value.dump();
      continue;
    }
    text += "[";
    for (size_t i = 0; i < value.size(); ++i) text += (i ? ",\n    " : "\n    ") + value[i].dump();
    text += "\n  ]";
  }
  return text + "\n}\n";
}

namespace {

std::string axes_text(const Eigen::Matrix3d& axes) {
  std::string text;
  for (int k = 0; k < 3; ++k)
    text += std::string(k ? ", " : "") + "[" + io::format_number(clean(axes(0, k)), 4) + ", " +
            io::format_number(clean(axes(1, k)), 4) + ", " +
            io::format_number(clean(axes(2, k)), 4) + "]";
  return text;
}

}  // namespace

void immersed_import_report(const ImportCommandResult& r, const ImportCommandOptions& options,
                            const std::string& output, nlohmann::json& j, io::MarkdownReport& md) {
  j["immersed"] = {{"solid", r.immersed_solid},
                   {"cad_volume", r.immersed_volume},
                   {"case_file", output},
                   {"solid_faces", nlohmann::json::parse(faces_json(r.faces).dump())}};
  // The case's grid follows the file's axes; the principal axes are what "frame": "principal"
  // would take (a part placed obliquely in its file gets a tighter grid along them).
  const Eigen::Matrix3d& axes = r.principal.axes;
  j["immersed"]["frame"] = "file";
  j["immersed"]["principal_axes"] = {{axes(0, 0), axes(1, 0), axes(2, 0)},
                                     {axes(0, 1), axes(1, 1), axes(2, 1)},
                                     {axes(0, 2), axes(1, 2), axes(2, 2)}};
  md.heading(1, "isospring import: " + options.input);
  md.paragraph("Path: immersed. " + r.path_reason + ".");
  md.paragraph("Wrote " + output + ", an immersed case of " +
               (r.immersed_solid >= 0 ? "solid " + std::to_string(r.immersed_solid)
                                      : std::string("the file's faces sewn into one solid")) +
               " (OpenCascade volume " + io::format_number(r.immersed_volume) +
               " m^3). Its support, load and material are placeholders (see its \"description\"): "
               "choose supports and loads from the faces below, by index or by a selector "
               "(plane, box, cylinder, STEP name), then run `isospring analyze " +
               output + " -o OUTDIR`. The grid follows the file's axes; the part's principal " +
               "axes of inertia are " + axes_text(r.principal.axes) +
               " (\"frame\": \"principal\" in \"geometry\" aligns the grid with them" +
               (r.principal.note.empty() ? std::string() : "; " + r.principal.note) + ").");
  std::vector<std::vector<std::string>> rows;
  for (const geometry::SolidFace& f : r.faces) {
    const auto v = [](const Eigen::Vector3d& x) {
      return "(" + io::format_number(clean(x.x()), 4) + ", " + io::format_number(clean(x.y()), 4) +
             ", " + io::format_number(clean(x.z()), 4) + ")";
    };
    std::string where;
    if (f.normal.norm() > 0) where = "normal " + v(f.normal);
    if (f.axis.norm() > 0)
      where = "axis " + v(f.axis) + " through " + v(f.axis_point) + ", radius " +
              io::format_number(f.radius, 4);
    rows.push_back({std::to_string(f.index), f.surface_type, f.name.empty() ? "-" : f.name,
                    io::format_number(f.area, 4), v(f.centroid), where.empty() ? "-" : where});
  }
  md.heading(2, "Faces of the solid (for supports and loads)");
  md.table({"face", "surface", "STEP name", "area [m^2]", "centroid [m]", "plane / cylinder"},
           rows);
}

}  // namespace isospring::workflows
