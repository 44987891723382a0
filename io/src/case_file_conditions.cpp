#include "case_file_conditions.hpp"

#include <map>
#include <set>

namespace isospring::io::case_conditions {
using case_json::Field;

namespace {

const char* const kSideNames[] = {"u0", "u1", "v0", "v1", "w0", "w1"};

int patch_index(const Field& item, const Context& context) {
  if (!item.has("patch")) return 0;
  const Field field = item.at("patch");
  const int patch = field.integer();
  const int count = static_cast<int>(context.patches->size());
  if (patch < 0 || patch >= count)
    field.fail(
        " = " + std::to_string(patch) + " does not exist; the geometry has " +
        std::to_string(count) +
        (count == 1 ? " patch (index 0)" : " patches (0.." + std::to_string(count - 1) + ")"));
  return patch;
}

analysis::Side read_side(const Field& item, const Context& context) {
  const int patch = patch_index(item, context);
  const Field field = item.at("side");
  const std::string name = field.string();
  const int param_dim = (*context.patches)[static_cast<size_t>(patch)].param_dim();
  std::vector<std::string> valid(kSideNames, kSideNames + 2 * param_dim);
  for (int i = 0; i < 6; ++i) {
    if (name != kSideNames[i]) continue;
    if (i / 2 >= param_dim)
      field.fail(": side '" + name + "' does not exist for a patch of parametric dimension " +
                 std::to_string(param_dim) + "; its sides are u0 u1 v0 v1" +
                 (param_dim == 3 ? " w0 w1" : ""));
    return analysis::Side{patch, i / 2, i % 2};
  }
  const std::string suggestion = case_json::closest_word(name, valid);
  field.fail(": unknown side '" + name + "'" +
             (suggestion.empty() ? "" : "; did you mean '" + suggestion + "'?") +
             " Sides are u0 u1 v0 v1" + (param_dim == 3 ? " w0 w1" : "") +
             " (u0: first knot of direction u, u1: last knot)");
}

/// A control point as a global index in its patch, or as a net position [i, j(, k)] where
/// negative entries count from the end (-1 is the last), which stays meaningful under refinement.
int read_control_point(const Field& field, const nurbs::Patch& patch) {
  const int count = patch.num_points();
  if (field.json().is_number_integer()) {
    const int index = field.integer();
    if (index < 0 || index >= count)
      field.fail(" = " + std::to_string(index) + " is out of range: the discretised patch has " +
                 std::to_string(count) + " control points (0.." + std::to_string(count - 1) + ")");
    return index;
  }
  const std::vector<Field> entries = field.elements();
  if (static_cast<int>(entries.size()) != patch.param_dim())
    field.fail(" must be an index or a net position of " + std::to_string(patch.param_dim()) +
               " integers [i, j" + (patch.param_dim() == 3 ? ", k]" : "]"));
  std::array<int, 3> ijk{0, 0, 0};
  for (size_t d = 0; d < entries.size(); ++d) {
    const int n = patch.num_points(static_cast<int>(d));
    int value = entries[d].integer();
    if (value < 0) value += n;
    if (value < 0 || value >= n)
      entries[d].fail(" is out of range: the discretised net has " + std::to_string(n) +
                      " control points in this direction (use 0.." + std::to_string(n - 1) +
                      ", or -1 for the last)");
    ijk[d] = value;
  }
  return patch.index(ijk[0], ijk[1], ijk[2]);
}

/// Components named "x", "y", "z" (no "z" in 2D).
std::array<bool, 3> read_components(const Field& field, int dimension) {
  std::array<bool, 3> fixed{false, false, false};
  for (const Field& entry : field.elements(false)) {
    const std::string name = entry.string();
    const int c = name == "x" ? 0 : name == "y" ? 1 : name == "z" ? 2 : -1;
    if (c < 0 || c >= dimension)
      entry.fail(": '" + name + "' is not a displacement component; use " +
                 (dimension == 3 ? "\"x\", \"y\", \"z\"" : "\"x\", \"y\" (2D)"));
    if (fixed[c]) entry.fail(": '" + name + "' is listed twice");
    fixed[c] = true;
  }
  return fixed;
}

/// A vector of the problem's dimension; 2D also accepts 3 entries with z = 0.
Eigen::Vector3d read_vector(const Field& field, const Context& context) {
  const Eigen::Vector3d v = field.vector(context.dimension, 3);
  if (context.dimension == 2 && v.z() != 0.0)
    field.fail(": the z component must be 0 for 2D geometry (plane stress/strain)");
  return v;
}

bool is_analytic_marker(const Field& field) {
  return field.json().is_string() && field.json().get<std::string>() == "analytic";
}

void require_analytic(const Field& field, const Context& context) {
  if (context.analytic == nullptr)
    field.fail(": \"analytic\" needs the case's top-level \"analytic\" object naming the solution");
}

analysis::Support read_support(const Field& item, const Context& context) {
  item.expect_object({"side", "patch", "control_point", "fix", "value", "symmetry"});
  analysis::Support support;
  const int patch = patch_index(item, context);
  if (item.has("control_point")) {
    if (item.has("side"))
      item.fail(
          ": give either \"side\" (every control point of a side) or \"control_point\", "
          "not both");
    support.side.patch = patch;
    support.control_point = read_control_point(item.at("control_point"),
                                               (*context.patches)[static_cast<size_t>(patch)]);
  } else if (item.has("side")) {
    support.side = read_side(item, context);
  } else {
    item.fail(": give \"side\" (e.g. \"u0\") or \"control_point\" for this support");
  }

  const bool symmetry = item.has("symmetry") && item.at("symmetry").boolean();
  if (symmetry) {
    if (item.has("fix") || item.has("value"))
      item.fail(
          ": \"symmetry\": true fixes the normal component; do not combine it with "
          "\"fix\" or \"value\"");
    if (support.control_point)
      item.fail(": \"symmetry\" needs a side (its normal), not a single control point");
    support.symmetry = true;
    return support;
  }
  if (!item.has("fix") && !item.has("value"))
    item.fail(": say what is fixed: \"fix\": [\"x\", \"y\"" +
              std::string(context.dimension == 3 ? ", \"z\"]" : "]") +
              ", a prescribed \"value\", or \"symmetry\": true");
  support.fixed = item.has("fix") ? read_components(item.at("fix"), context.dimension)
                                  : std::array<bool, 3>{true, true, context.dimension == 3};
  if (item.has("value")) {
    const Field value = item.at("value");
    if (is_analytic_marker(value)) {
      require_analytic(value, context);
      support.value_function = context.analytic->displacement;
    } else {
      support.value = read_vector(value, context);
    }
  }
  return support;
}

/// (patch, dir, end) -> the components fixed on every control point of that side.
std::map<std::array<int, 3>, std::array<bool, 3>> fixed_sides(
    const std::vector<analysis::Support>& supports) {
  std::map<std::array<int, 3>, std::array<bool, 3>> sides;
  for (const analysis::Support& s : supports) {
    if (s.control_point || s.symmetry) continue;
    auto& fixed = sides[{s.side.patch, s.side.dir, s.side.end}];
    for (int c = 0; c < 3; ++c) fixed[c] = fixed[c] || s.fixed[c];
  }
  return sides;
}

void reject_load_on_fixed_side(const Field& side_field, const analysis::Side& side,
                               const std::vector<analysis::Support>& supports,
                               const Context& context) {
  const auto sides = fixed_sides(supports);
  const auto it = sides.find({side.patch, side.dir, side.end});
  if (it == sides.end()) return;
  for (int c = 0; c < context.dimension; ++c)
    if (!it->second[c]) return;
  side_field.fail(": side " + std::string(kSideNames[2 * side.dir + side.end]) + " of patch " +
                  std::to_string(side.patch) +
                  " is fully fixed by \"boundary\", so a load there does nothing; load another "
                  "side or free a component of this one");
}

analysis::LoadCase read_load_case(const Field& item, const std::vector<analysis::Support>& supports,
                                  const Context& context) {
  item.expect_object(
      {"id", "description", "tractions", "pressures", "body_force", "gravity", "point_loads"});
  analysis::LoadCase load_case;
  load_case.id = item.at("id").string();
  if (load_case.id.empty() || load_case.id.find_first_of("/\\ \t\n") != std::string::npos)
    item.at("id").fail(
        ": must be a non-empty name without spaces or slashes (it names output "
        "files)");
  if (item.has("description")) item.at("description").string();

  if (item.has("tractions")) {
    for (const Field& entry : item.at("tractions").elements()) {
      entry.expect_object({"side", "patch", "value"});
      analysis::Traction traction;
      traction.side = read_side(entry, context);
      reject_load_on_fixed_side(entry.at("side"), traction.side, supports, context);
      const Field value = entry.at("value");
      if (is_analytic_marker(value)) {
        require_analytic(value, context);
        const auto stress = context.analytic->stress;
        traction.function = [stress](const Eigen::Vector3d& x, const Eigen::Vector3d& n) {
          return Eigen::Vector3d(stress(x) * n);
        };
      } else {
        traction.value = read_vector(value, context);
      }
      load_case.tractions.push_back(traction);
    }
  }
  if (item.has("pressures")) {
    for (const Field& entry : item.at("pressures").elements()) {
      entry.expect_object({"side", "patch", "value"});
      analysis::Pressure pressure;
      pressure.side = read_side(entry, context);
      reject_load_on_fixed_side(entry.at("side"), pressure.side, supports, context);
      pressure.value = entry.at("value").number();
      load_case.pressures.push_back(pressure);
    }
  }
  if (item.has("point_loads")) {
    for (const Field& entry : item.at("point_loads").elements()) {
      entry.expect_object({"patch", "control_point", "force"});
      analysis::PointLoad load;
      load.patch = patch_index(entry, context);
      load.control_point = read_control_point(entry.at("control_point"),
                                              (*context.patches)[static_cast<size_t>(load.patch)]);
      load.force = read_vector(entry.at("force"), context);
      load_case.point_loads.push_back(load);
    }
  }
  if (item.has("body_force")) load_case.body_force = read_vector(item.at("body_force"), context);
  if (item.has("gravity")) {
    load_case.gravity = read_vector(item.at("gravity"), context);
    if (context.density <= 0 && load_case.gravity.norm() > 0)
      item.at("gravity").fail(": gravity needs material.density > 0 (it loads density * g)");
  }
  // A load case whose every entry is zero solves to u = 0, which is almost always a mistake
  // (a forgotten value or a unit slip), so it is rejected like a load case without entries.
  // Tractions given by the analytic solution count as loads.
  // (A component test, not norm() != 0: the norm of [1e-200, 0, 0] underflows to zero.)
  const auto nonzero = [](const Eigen::Vector3d& v) { return (v.array() != 0.0).any(); };
  bool loaded = nonzero(load_case.body_force) || nonzero(load_case.gravity);
  for (const auto& t : load_case.tractions) loaded = loaded || t.function || nonzero(t.value);
  for (const auto& p : load_case.pressures) loaded = loaded || p.value != 0;
  for (const auto& l : load_case.point_loads) loaded = loaded || nonzero(l.force);
  if (!loaded)
    item.fail(" (id '" + load_case.id +
              "') has no load: no entry, or every traction, pressure, point load, body force and "
              "gravity is zero; give a non-zero load");
  return load_case;
}

}  // namespace

std::vector<analysis::Support> read_supports(const Field& boundary, const Context& context) {
  std::vector<analysis::Support> supports;
  for (const Field& item : boundary.elements(false))
    supports.push_back(read_support(item, context));
  return supports;
}

std::vector<analysis::LoadCase> read_load_cases(const Field& load_cases,
                                                const std::vector<analysis::Support>& supports,
                                                const Context& context) {
  std::vector<analysis::LoadCase> out;
  std::set<std::string> ids;
  for (const Field& item : load_cases.elements(false)) {
    out.push_back(read_load_case(item, supports, context));
    if (!ids.insert(out.back().id).second)
      item.at("id").fail(": load case id '" + out.back().id +
                         "' is used twice; ids must be unique (they name output files)");
  }
  return out;
}

}  // namespace isospring::io::case_conditions
