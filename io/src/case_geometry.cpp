#include "isospring/io/case_geometry.hpp"

#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <sstream>

#include "case_file_json.hpp"
#include "isospring/geometry/cad.hpp"
#include "isospring/geometry/plate_with_central_hole.hpp"
#include "isospring/geometry/primitives.hpp"
#include "isospring/geometry/specimen_shoulder.hpp"
#include "isospring/io/json_text.hpp"
#include "isospring/io/patch_file.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::io {

namespace {

using geometry::Patches;
using nurbs::InputError;

constexpr double kDegree = M_PI / 180.0;

// Reads the fields of one geometry object and reports problems with the full field path.
class GeometryFields {
 public:
  GeometryFields(const nlohmann::json& object, std::string prefix, std::string type)
      : object_(object), prefix_(std::move(prefix)), type_(std::move(type)) {}

  [[noreturn]] void fail(const std::string& field, const std::string& what) const {
    throw InputError(prefix_ + field + " " + what);
  }

  bool has(const std::string& field) const {
    used_.insert(field);
    return object_.contains(field);
  }

  double number(const std::string& field) const {
    used_.insert(field);
    if (!object_.contains(field))
      fail(field,
           "is missing; a " + type_ +
               " needs it (geometry types and their fields: docs/case-files.md, 'geometry')");
    return to_number(object_.at(field), field);
  }

  double number_or(const std::string& field, double fallback) const {
    return has(field) ? number(field) : fallback;
  }

  /// An angle in degrees in (0, max_degrees], returned in radians.
  double sweep_or(const std::string& field, double fallback_degrees, double max_degrees) const {
    const double a = number_or(field, fallback_degrees);
    if (!(a > 0.0 && a <= max_degrees))
      fail(field, "must be in (0, " + std::to_string(static_cast<int>(max_degrees)) +
                      "] degrees, got " + std::to_string(a));
    return a * kDegree;
  }

  int integer_or(const std::string& field, int fallback, std::initializer_list<int> allowed) const {
    if (!has(field)) return fallback;
    const nlohmann::json& v = object_.at(field);
    if (const std::optional<int> x = json_int(v))
      for (int a : allowed)
        if (*x == a) return a;
    std::ostringstream msg;
    msg << "must be one of";
    for (int a : allowed) msg << " " << a;
    fail(field, msg.str() + " for a " + type_ + ", got " + v.dump());
  }

  std::vector<double> numbers(const std::string& field, size_t count) const {
    used_.insert(field);
    if (!object_.contains(field)) fail(field, "is missing; a " + type_ + " needs it");
    const nlohmann::json& v = object_.at(field);
    if (!v.is_array() || v.size() != count)
      fail(field, "must have " + std::to_string(count) + " numbers for a " + type_ + ", got " +
                      (v.is_array() ? std::to_string(v.size()) : v.dump()));
    std::vector<double> values;
    for (size_t i = 0; i < count; ++i)
      values.push_back(to_number(v[i], field + "[" + std::to_string(i) + "]"));
    return values;
  }

  std::string text(const std::string& field) const {
    used_.insert(field);
    if (!object_.contains(field) || !object_.at(field).is_string())
      fail(field, "must be a string (a file name) for a " + type_);
    return object_.at(field).get<std::string>();
  }

  /// Call after reading: any field not read is unknown for this type.
  void reject_unknown() const {
    std::vector<std::string> allowed(used_.begin(), used_.end());
    allowed.push_back("type");
    case_json::reject_unknown_fields(object_, allowed, prefix_);
  }

  const std::string& prefix() const { return prefix_; }
  const nlohmann::json& object() const { return object_; }

 private:
  // The type check is case_json::Field's, the one wording of every io reader.
  double to_number(const nlohmann::json& v, const std::string& field) const {
    return case_json::Field::at_where(v, prefix_ + field).number();
  }

  const nlohmann::json& object_;
  std::string prefix_;
  std::string type_;
  mutable std::set<std::string> used_;
};

Patches build(const nlohmann::json& geometry, const std::filesystem::path& case_dir,
              const std::string& prefix);

using Builder = std::function<Patches(const GeometryFields&, const std::filesystem::path&)>;

const std::map<std::string, Builder>& builders() {
  static const std::map<std::string, Builder> table{
      {"rectangle",
       [](const GeometryFields& f, const auto&) {
         const auto s = f.numbers("size", 2);
         return geometry::rectangle(s[0], s[1]);
       }},
      {"square",
       [](const GeometryFields& f, const auto&) {
         const double s = f.number("size");
         return geometry::rectangle(s, s);
       }},
      {"disk",
       [](const GeometryFields& f, const auto&) {
         const double r = f.number("radius");
         if (f.integer_or("patches", 1, {1, 5}) == 1) {
           if (f.has("inner_fraction"))
             f.fail("inner_fraction", "only applies to the 5-patch disk (\"patches\": 5)");
           return geometry::disk(r);
         }
         return geometry::disk_five_patch(r, f.number_or("inner_fraction", 0.5));
       }},
      {"ellipse",
       [](const GeometryFields& f, const auto&) {
         const auto r = f.numbers("radii", 2);
         return geometry::ellipse(r[0], r[1]);
       }},
      {"annulus",
       [](const GeometryFields& f, const auto&) {
         return geometry::annulus(f.number("inner_radius"), f.number("outer_radius"),
                                  f.number_or("start_angle", 0.0) * kDegree,
                                  f.sweep_or("sweep_angle", 90.0, 360.0));
       }},
      {"plate_with_hole",
       [](const GeometryFields& f, const auto&) {
         const double R = f.number("hole_radius"), L = f.number("half_width");
         return f.integer_or("patches", 1, {1, 2}) == 1
                    ? geometry::plate_with_hole_quarter(R, L)
                    : geometry::plate_with_hole_quarter_two_patch(R, L);
       }},
      {"plate_with_central_hole",
       [](const GeometryFields& f, const auto&) {
         const auto s = f.numbers("size", 2);
         Patches plate = geometry::plate_with_central_hole(s[0], s[1], f.number("hole_radius"));
         if (!f.has("shoulder")) return plate;
         // [straight_length, fillet_radius, shoulder_width]: the specimen widening at x = 0.
         const auto h = f.numbers("shoulder", 3);
         return geometry::add_specimen_shoulder(std::move(plate), s[1], {h[0], h[1], h[2]});
       }},
      {"box",
       [](const GeometryFields& f, const auto&) {
         const auto s = f.numbers("size", 3);
         return geometry::box(s[0], s[1], s[2]);
       }},
      {"cube",
       [](const GeometryFields& f, const auto&) {
         const double s = f.number("size");
         return geometry::box(s, s, s);
       }},
      {"tube",
       [](const GeometryFields& f, const auto&) {
         return geometry::tube_sector(f.number("inner_radius"), f.number("outer_radius"),
                                      f.number("length"), f.number_or("start_angle", 0.0) * kDegree,
                                      f.sweep_or("sweep_angle", 90.0, 360.0));
       }},
      {"torus",
       [](const GeometryFields& f, const auto&) {
         const bool by_axes = f.has("major_radius") || f.has("minor_radius");
         const bool by_extent = f.has("inner_radius") || f.has("outer_radius");
         if (by_axes == by_extent)
           f.fail("major_radius",
                  "and minor_radius, or inner_radius and outer_radius (not both pairs), must be "
                  "given for a torus");
         if (by_axes)
           return geometry::solid_torus(f.number("major_radius"), f.number("minor_radius"));
         const double ri = f.number("inner_radius"), ro = f.number("outer_radius");
         if (!(ri > 0.0 && ro > ri))
           f.fail("outer_radius", "must exceed inner_radius > 0 for a torus");
         return geometry::solid_torus((ro + ri) / 2, (ro - ri) / 2);
       }},
      {"hollow_sphere",
       [](const GeometryFields& f, const auto&) {
         return geometry::hollow_sphere_sector(f.number("inner_radius"), f.number("outer_radius"),
                                               f.sweep_or("polar_angle", 90.0, 180.0),
                                               f.sweep_or("azimuth_angle", 90.0, 360.0));
       }},
      {"spheroid",
       [](const GeometryFields& f, const auto&) {
         return geometry::prolate_spheroid(f.number("half_length"), f.number("radius"));
       }},
      {"coupled_spheroid",
       [](const GeometryFields&, const auto&) { return geometry::coupled_spheroid(); }},
      {"thin_plate",
       [](const GeometryFields& f, const std::filesystem::path& dir) {
         if (!f.has("region")) f.fail("region", "is missing; a thin_plate needs a 2D geometry");
         const double t = f.number("thickness");
         const Patches region = build(f.object().at("region"), dir, f.prefix() + "region.");
         for (const auto& p : region)
           if (p.param_dim() != 2 || p.physical_dim() != 2)
             f.fail("region", "must be a 2D (planar, z = 0) geometry to extrude");
         return geometry::thin_plate(region, t);
       }},
      {"cad",
       [](const GeometryFields& f, const std::filesystem::path& dir) {
         const std::filesystem::path file = dir / f.text("file");
         if (!std::filesystem::exists(file))
           f.fail("file", "'" + file.string() +
                              "' does not exist (relative names are resolved "
                              "against the case file's folder)");
         const double thickness = f.number_or("thickness", 0.0);
         std::vector<int> faces;
         if (f.has("faces")) {
           const nlohmann::json& list = f.object().at("faces");
           if (!list.is_array()) f.fail("faces", "must be a list of face indices (0-based)");
           for (const auto& v : list) {
             const std::optional<int> index = json_int(v);
             if (!index) f.fail("faces", "must hold integers, got " + v.dump());
             faces.push_back(*index);
           }
         }
         std::vector<int> solids;
         if (f.has("solids")) {
           if (f.has("faces") || thickness > 0.0)
             f.fail("solids",
                    "cannot be combined with faces or thickness: choose solids "
                    "(volumes) or faces (surfaces, optionally extruded)");
           const nlohmann::json& list = f.object().at("solids");
           if (!list.is_array()) f.fail("solids", "must be a list of solid indices (0-based)");
           for (const auto& v : list) {
             const std::optional<int> index = json_int(v);
             if (!index) f.fail("solids", "must hold integers, got " + v.dump());
             solids.push_back(*index);
           }
           return geometry::cad_solid_patches(geometry::read_cad(file), solids);
         }
         return geometry::cad_patches(geometry::read_cad(file), thickness, faces);
       }},
      {"patches",
       [](const GeometryFields& f, const std::filesystem::path& dir) {
         const std::filesystem::path file = dir / f.text("file");
         if (!std::filesystem::exists(file))
           f.fail("file", "'" + file.string() +
                              "' does not exist (relative names are resolved "
                              "against the case file's folder)");
         return read_patch_file(file);
       }},
  };
  return table;
}

Patches build(const nlohmann::json& geometry, const std::filesystem::path& case_dir,
              const std::string& prefix) {
  if (!geometry.is_object())
    throw InputError(prefix.substr(0, prefix.size() - 1) +
                     " must be an object with a \"type\" field, e.g. {\"type\": \"box\", "
                     "\"size\": [1, 0.1, 0.1]}");
  if (!geometry.contains("type") || !geometry.at("type").is_string())
    throw InputError(prefix + "type is missing or not a string; one of: " + [] {
      std::string names;
      for (const auto& [name, b] : builders()) names += (names.empty() ? "" : ", ") + name;
      return names;
    }());
  const std::string type = geometry.at("type").get<std::string>();
  if (type == "immersed")
    throw InputError(prefix +
                     "type 'immersed' is run by `isospring analyze` and `isospring study` (and "
                     "Python's analyze_immersed) only (the immersed path, docs/immersed.md); "
                     "calibrate, identify and the exports take body-fitted geometry: a "
                     "\"cad\" geometry of a part `isospring import` makes volumes of, or a "
                     "geometry type listed in docs/case-files.md");
  const auto it = builders().find(type);
  if (it == builders().end()) {
    std::string names;
    for (const auto& [name, b] : builders()) names += (names.empty() ? "" : ", ") + name;
    throw InputError(prefix + "type '" + type + "' is unknown; use one of: " + names);
  }
  const GeometryFields fields(geometry, prefix, type);
  Patches patches;
  try {
    patches = it->second(fields, case_dir);
  } catch (const InputError& e) {
    // Primitive parameter errors name the parameter; add where it came from.
    const std::string what = e.what();
    if (what.rfind(prefix.substr(0, prefix.find(':')), 0) == 0) throw;  // already names the case
    throw InputError(prefix.substr(0, prefix.size() - 1) + ": " + what);
  }
  fields.reject_unknown();
  return patches;
}

}  // namespace

std::vector<nurbs::Patch> build_case_geometry(const nlohmann::json& geometry,
                                              const std::filesystem::path& case_dir,
                                              const std::string& case_file_name) {
  return build(geometry, case_dir, case_file_name + ": geometry.");
}

std::string geometry_types_help() {
  return R"(Geometry types ("geometry": {"type": ..., fields}); lengths in m, angles in degrees:
  rectangle         size [lx, ly]                       2D, u along x, v along y
  square            size L                              2D
  disk              radius [patches 1|5, inner_fraction] 2D, 1 patch (3x3 rational) or 5 patches
  ellipse           radii [a, b]                        2D
  annulus           inner_radius outer_radius [start_angle 0, sweep_angle 90]   2D, u radial
  plate_with_hole   hole_radius half_width [patches 1|2]   2D quarter plate (x <= 0, y >= 0)
  plate_with_central_hole  size [lx, ly] hole_radius [shoulder]   2D, hole at (lx/2, ly/2); 6 patches, ends = side v1 of patches 0 and 5;
                    shoulder [straight_length, fillet_radius, width]: the specimen widening left of x = 0 (2 more patches; left end = side v1 of the last)
  box               size [lx, ly, lz]                   u along x, v along y, w along z
  cube              size L
  tube              inner_radius outer_radius length [start_angle 0, sweep_angle 90]
  torus             major_radius minor_radius | inner_radius outer_radius
  hollow_sphere     inner_radius outer_radius [polar_angle 90, azimuth_angle 90]
  spheroid          half_length radius              prolate, long axis z
  coupled_spheroid  (no fields)                     [S15] Table 5.1: two spheroids, z in [0, 4]
  thin_plate        region (a 2D geometry) thickness   extruded along +z
  patches           file                            a patch file (JSON)
  cad               file [thickness, faces | solids] STEP/IGES part (see `isospring import`)
)";
}

}  // namespace isospring::io
