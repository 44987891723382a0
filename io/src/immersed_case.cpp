// Reader of immersed case files (see immersed_case.hpp).
#include "isospring/io/immersed_case.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <set>

#include "case_file_json.hpp"
#include "case_volumetric.hpp"
#include "immersed_faces.hpp"
#include "isospring/io/atomic_file.hpp"
#include "isospring/io/json_text.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::io {
using case_json::Field;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

std::array<bool, 3> read_components(const Field& field) {
  std::array<bool, 3> fixed{false, false, false};
  for (const Field& entry : field.elements(false)) {
    const std::string name = entry.string();
    const int c = name == "x" ? 0 : name == "y" ? 1 : name == "z" ? 2 : -1;
    if (c < 0)
      entry.fail(": '" + name + "' is not a displacement component; use \"x\", \"y\", \"z\"");
    if (fixed[c]) entry.fail(": '" + name + "' is listed twice");
    fixed[c] = true;
  }
  return fixed;
}

// "grading": {"face": F, "smallest": m, "ratio": r}, or a list of such items: cells graded towards
// face F's outline (F an index or a selector, as for supports), or with "plane": {"axis": "x",
// "at": m} instead of "face", towards that plane.
void read_grading(const Field& field, const geometry::CadSolid& in_frame, ImmersedCase& c) {
  detail::ImmersedFaceChooser chooser(*c.cad);
  const std::vector<Field> items =
      field.json().is_array() ? field.elements(false) : std::vector<Field>{field};
  for (const Field& item : items) {
    item.expect_object({"face", "plane", "smallest", "ratio"});
    const double smallest = item.at("smallest").at_least(0, true);
    const double ratio = item.has("ratio") ? item.at("ratio").within(1, 10, false, false) : 1.5;
    if (item.has("face") == item.has("plane"))
      item.fail(": give either \"face\" or \"plane\": {\"axis\": \"x\", \"at\": m}");
    if (item.has("plane")) {
      const Field plane = item.at("plane");
      plane.expect_object({"axis", "at"});
      const std::string axis = plane.at("axis").string();
      const int k = axis == "x" ? 0 : axis == "y" ? 1 : axis == "z" ? 2 : -1;
      if (k < 0) plane.at("axis").fail(": '" + axis + "' is not an axis; use \"x\", \"y\", \"z\"");
      c.immersion.grading.push_back({k, plane.at("at").number(), smallest, ratio});
      continue;
    }
    for (int face : chooser.faces(item))
      for (const geometry::GradingPlane& p :
           geometry::grading_towards_face(in_frame, face, smallest, ratio))
        c.immersion.grading.push_back(p);
  }
}

// "frame": "principal" (the part's principal axes of inertia) or {"x": [...], "y": [...]} (the
// grid's x and y axes in world coordinates, z = x cross y): the axes the background grid follows.
void read_frame(const Field& field, ImmersedCase& c) {
  if (field.json().is_string()) {
    if (field.string() == "file") return;
    if (field.string() != "principal")
      field.fail(": '" + field.string() +
                 "' is not a frame; give \"principal\" (the part's principal axes of inertia), "
                 "\"file\" (its own axes) or {\"x\": [...], \"y\": [...]}");
    const geometry::PrincipalFrame principal = geometry::principal_frame(*c.cad);
    c.immersion.frame = principal.axes;
    c.frame = "principal";
    c.frame_note = principal.note;
    return;
  }
  field.expect_object({"x", "y"});
  const Eigen::Vector3d x = field.at("x").vector(3), y = field.at("y").vector(3);
  if (!(x.norm() > 0.0) || !(y.norm() > 0.0))
    field.fail(": \"x\" and \"y\" must be nonzero directions (they are normalised)");
  const Eigen::Vector3d ux = x.normalized(), uy = y.normalized();
  if (std::abs(ux.dot(uy)) > 1e-9)
    field.fail(": \"x\" and \"y\" must be at right angles (their unit vectors' dot product is " +
               std::to_string(ux.dot(uy)) + ", above 1e-9)");
  c.immersion.frame.col(0) = ux;
  c.immersion.frame.col(1) = uy;
  c.immersion.frame.col(2) = ux.cross(uy);
  c.frame = "user";
}

void read_geometry(const Field& root, const fs::path& case_file, ImmersedCase& c) {
  const Field g = root.at("geometry");
  g.expect_object({"type", "file", "solid", "cells", "cell_size", "degree", "margin", "gauss",
                   "max_depth", "grading", "keep_planar_faces", "frame"});
  const Field file = g.at("file");
  c.part = case_file.parent_path() / file.string();
  if (!fs::is_regular_file(c.part))
    file.fail(": '" + file.string() + "' does not exist (looked for " + c.part.string() +
              "; paths are relative to the case file's folder)");
  if (g.has("solid")) c.solid = g.at("solid").integer_at_least(0);
  geometry::ImmersionOptions& o = c.immersion;
  if (g.has("degree")) o.degree = g.at("degree").integer_within(1, 6);
  if (g.has("cells") && g.has("cell_size"))
    g.fail(": give either \"cells\" or \"cell_size\", not both");
  if (g.has("cells")) {
    const std::vector<Field> n = g.at("cells").elements(false);
    if (n.size() != 3) g.at("cells").fail(" must be 3 integers [nx, ny, nz]");
    for (int d = 0; d < 3; ++d) o.cells[d] = n[static_cast<size_t>(d)].integer_within(1, 1000);
  }
  if (g.has("cell_size")) o.cell_size = g.at("cell_size").at_least(0, true);
  if (g.has("margin")) o.margin = g.at("margin").non_negative();
  if (g.has("gauss")) o.gauss = g.at("gauss").integer_within(o.degree + 1, 20);
  if (g.has("max_depth")) o.max_depth = g.at("max_depth").integer_within(0, 8);
  try {
    c.cad = std::make_shared<const geometry::CadSolid>(geometry::read_cad_solid(c.part, c.solid));
  } catch (const nurbs::InputError& e) {
    // A missing or wrong solid choice is the "solid" field's fix; anything else the file's.
    const std::string what = e.what();
    if (what.find("solid") == std::string::npos) file.fail(": " + what);
    (g.has("solid") ? g.at("solid") : g).fail(": " + what);
  }
  if (g.has("frame")) read_frame(g.at("frame"), c);
  // Grading planes and kept planes are coordinates along the grid's axes: taken from the part
  // turned into the frame.
  const geometry::CadSolid in_frame = o.frame == Eigen::Matrix3d::Identity()
                                          ? *c.cad
                                          : geometry::transform_solid(*c.cad, o.frame.transpose());
  if (g.has("grading")) read_grading(g.at("grading"), in_frame, c);
  // The planar faces normal to an axis on grid planes, so that they cut no cell.
  if (g.has("keep_planar_faces") && g.at("keep_planar_faces").boolean())
    o.breaks = geometry::planar_face_coordinates(in_frame);
}

analysis::Material read_material(const Field& root) {
  const Field field = root.at("material");
  field.expect_object({"E", "nu", "density"});
  analysis::Material m;
  m.youngs_modulus = field.at("E").at_least(0, true);
  m.poisson_ratio = field.at("nu").within(-1, 0.5, true, true);
  if (field.has("density")) m.density = field.at("density").non_negative();
  return m;
}

/// "analysis": {"type": "solid", "volumetric": "displacement" | "bbar", "ghost_fraction": f,
/// "ghost_penalty": g}: "volumetric" is the key of body-fitted cases; an immersed CAD part is
/// always a solid, so "type" may only say so. The ghost penalty's keys set the stabilisation of
/// cut cells (analysis::ImmersedOptions): the share of the part below which a cut cell's faces
/// are penalised, and the penalty's strength (0 switches it off).
void read_immersed_analysis(const Field& root, ImmersedCase& c) {
  if (!root.has("analysis")) return;
  const Field field = root.at("analysis");
  field.expect_object({"type", "volumetric", "ghost_fraction", "ghost_penalty"});
  if (field.has("type") && field.at("type").string() != "solid")
    field.at("type").fail(": an immersed CAD part is a 3D solid; '" + field.at("type").string() +
                          "' is not available for it. Use \"solid\" or leave \"type\" out");
  c.volumetric = case_json::read_volumetric(field, analysis::Formulation::kSolid);
  if (field.has("ghost_fraction")) c.ghost_fraction = field.at("ghost_fraction").within(0.0, 1.0);
  if (field.has("ghost_penalty")) c.ghost_penalty = field.at("ghost_penalty").non_negative();
}

std::vector<analysis::ImmersedSupport> read_supports(const Field& boundary,
                                                     detail::ImmersedFaceChooser& chooser) {
  std::vector<analysis::ImmersedSupport> supports;
  for (const Field& item : boundary.elements(false)) {
    item.expect_object({"face", "fix", "value", "symmetry"});
    analysis::ImmersedSupport s;
    const std::vector<int> faces = chooser.faces(item);
    s.symmetry = item.has("symmetry") && item.at("symmetry").boolean();
    if (s.symmetry && (item.has("fix") || item.has("value")))
      item.fail(": a symmetry support holds the normal component; drop \"fix\" and \"value\"");
    if (!s.symmetry) {
      if (!item.has("fix"))
        item.fail(
            ": give \"fix\": [\"x\", \"y\", \"z\"] (the held components) or "
            "\"symmetry\": true");
      s.fixed = read_components(item.at("fix"));
      if (item.has("value")) s.value = item.at("value").vector(3);
    }
    // A selector may match several faces: the same support on each.
    for (int face : faces) {
      s.face = face;
      supports.push_back(s);
    }
  }
  return supports;
}

ImmersedLoadCase read_load_case(const Field& item, const ImmersedCase& c,
                                detail::ImmersedFaceChooser& chooser, std::set<std::string>& ids) {
  item.expect_object({"id", "description", "tractions", "pressures", "body_force", "gravity"});
  ImmersedLoadCase load;
  load.id = item.at("id").string();
  if (load.id.empty() || !ids.insert(load.id).second)
    item.at("id").fail(": '" + load.id +
                       "' is empty or used twice; give each load case its own id");
  bool loaded = false;
  if (item.has("tractions"))
    for (const Field& entry : item.at("tractions").elements()) {
      entry.expect_object({"face", "value"});
      analysis::ImmersedTraction t;
      t.value = entry.at("value").vector(3);
      loaded = loaded || t.value.norm() > 0;
      for (int face : chooser.faces(entry)) {
        t.face = face;
        load.tractions.push_back(t);
      }
    }
  if (item.has("pressures"))
    for (const Field& entry : item.at("pressures").elements()) {
      entry.expect_object({"face", "value"});
      analysis::ImmersedPressure p;
      p.value = entry.at("value").number();
      loaded = loaded || p.value != 0;
      for (int face : chooser.faces(entry)) {
        p.face = face;
        load.pressures.push_back(p);
      }
    }
  if (item.has("body_force")) load.body_force = item.at("body_force").vector(3);
  if (item.has("gravity")) {
    load.gravity = item.at("gravity").vector(3);
    if (c.material.density <= 0 && load.gravity.norm() > 0)
      item.at("gravity").fail(": gravity needs material.density > 0 (it loads density * g)");
  }
  loaded = loaded || load.body_force.norm() > 0 || load.gravity.norm() > 0;
  if (!loaded)
    item.fail(": every traction, pressure, body force and gravity is zero; give a non-zero load");
  return load;
}

}  // namespace

bool is_immersed_case(const json& document) {
  if (!document.is_object() || !document.contains("geometry")) return false;
  const json& g = document.at("geometry");
  return g.is_object() && g.contains("type") && g.at("type") == "immersed";
}

ImmersedCase build_immersed_case(const json& document, const fs::path& case_file) {
  const std::string label = case_file.filename().string();
  if (!document.is_object())
    throw nurbs::InputError(label + ": a case file is a JSON object {...}");
  const Field root(document, label, "");
  // "faces" is the list `isospring import` writes for the user to choose from; not read here.
  // "calibration" is read by `isospring calibrate` (io::read_calibration_settings),
  // "measurements" by `isospring identify` (io::read_measurement_settings).
  root.expect_object({"schema_version", "name", "description", "units", "geometry", "material",
                      "boundary", "load_cases", "faces", "output", "analytic", "calibration",
                      "measurements", "analysis"});
  ImmersedCase c;
  c.file = case_file;
  c.raw = document;
  c.name = root.has("name") ? root.at("name").string() : case_file.stem().string();
  if (root.has("output")) {
    const Field output = root.at("output");
    output.expect_object({"cells"});
    if (output.has("cells")) c.write_cells = output.at("cells").boolean();
  }
  c.material = read_material(root);
  read_immersed_analysis(root, c);
  read_geometry(root, case_file, c);
  detail::ImmersedFaceChooser chooser(*c.cad);
  c.supports = read_supports(root.at("boundary"), chooser);
  std::set<std::string> ids;
  for (const Field& item : root.at("load_cases").elements(false))
    c.load_cases.push_back(read_load_case(item, c, chooser, ids));
  if (root.has("analytic"))  // a solid: only the 3D closed forms apply
    c.analytic = make_analytic_solution(root.at("analytic").json(), c.material,
                                        analysis::Formulation::kSolid, root.at("analytic").where());
  return c;
}

ImmersedCase read_immersed_case(const fs::path& path) {
  const json document =
      parse_json_text(read_text_file(path, "case file"), path.string(), "case file");
  return build_immersed_case(document, path);
}

std::string volumetric_key(analysis::Volumetric volumetric) {
  return volumetric == analysis::Volumetric::kBbar ? "bbar" : "displacement";
}

std::string volumetric_sentence(analysis::Volumetric volumetric) {
  return volumetric == analysis::Volumetric::kBbar
             ? "B-bar: the volumetric strain is its mean over each cell's part (mean dilatation)"
             : "displacement formulation";
}

analysis::ImmersedOptions immersed_options(const ImmersedCase& c, const ImmersedLoadCase& load) {
  analysis::ImmersedOptions o;
  o.formulation = analysis::Formulation::kSolid;
  o.material = c.material;
  o.volumetric = c.volumetric;
  o.ghost_fraction = c.ghost_fraction;
  o.ghost_penalty = c.ghost_penalty;
  o.supports = c.supports;
  o.tractions = load.tractions;
  o.pressures = load.pressures;
  o.body_force = load.body_force;
  o.gravity = load.gravity;
  return o;
}

}  // namespace isospring::io
