#include "case_file_conditions.hpp"

#include <algorithm>
#include <limits>
#include <map>
#include <set>
#include <sstream>

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

/// Every patch side lying on the plane of `"where": {"x": 0.05}` (one of x, y, z): all its
/// control points on the plane (a NURBS side lies in a plane exactly when its control points do),
/// to 1e-6 of the model's bounding-box diagonal, the tolerance the multipatch gluing uses. So a
/// CAD part's faces are named by where they are, not by patch and side, and the choice survives
/// refinement and a new cut of the part.
std::vector<analysis::Side> sides_on_plane(const Field& where, const Context& context) {
  where.expect_object({"x", "y", "z"});
  const std::vector<std::string> axes = context.dimension == 3
                                            ? std::vector<std::string>{"x", "y", "z"}
                                            : std::vector<std::string>{"x", "y"};
  int axis = -1;
  for (int a = 0; a < 3; ++a)
    if (where.has(std::string(1, "xyz"[a]))) {
      if (axis >= 0) where.fail(": give one coordinate, e.g. {\"x\": 0.05} (the plane x = 0.05)");
      axis = a;
    }
  if (axis < 0) where.fail(": give one coordinate, e.g. {\"x\": 0.05} (the plane x = 0.05)");
  const std::string name(1, "xyz"[axis]);
  if (axis >= context.dimension) where.at(name).fail(": 2D geometry has no z; use x or y");
  const double value = where.at(name).number();
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const nurbs::Patch& patch : *context.patches)
    for (const Eigen::Vector3d& x : patch.control_points()) {
      lo = lo.cwiseMin(x);
      hi = hi.cwiseMax(x);
    }
  const double tolerance = 1e-6 * (hi - lo).norm();
  std::vector<analysis::Side> sides;
  for (int p = 0; p < static_cast<int>(context.patches->size()); ++p) {
    const nurbs::Patch& patch = (*context.patches)[static_cast<size_t>(p)];
    for (int dir = 0; dir < patch.param_dim(); ++dir)
      for (int end = 0; end < 2; ++end) {
        const int layer = end == 0 ? 0 : patch.num_points(dir) - 1;
        bool on = true;
        for (int i = 0; i < patch.num_points() && on; ++i)
          if (patch.net_position(i)[static_cast<size_t>(dir)] == layer)
            on = std::abs(patch.control_point(i)[axis] - value) <= tolerance;
        if (on) sides.push_back({p, dir, end});
      }
  }
  if (sides.empty()) {
    std::ostringstream why;
    why << ": no patch side lies on the plane " << name << " = " << value << " (the model spans "
        << name << " from " << lo[axis] << " to " << hi[axis]
        << "); give the coordinate of a flat face of the part, in metres";
    where.at(name).fail(why.str());
  }
  return sides;
}

/// The sides an entry names: "side" (+ "patch"), or every side on the plane of "where".
std::vector<analysis::Side> read_sides(const Field& item, const Context& context) {
  if (!item.has("where")) return {read_side(item, context)};
  if (item.has("side") || item.has("patch"))
    item.fail(
        ": give either \"where\" (every patch side on a plane) or \"side\" and "
        "\"patch\", not both");
  return sides_on_plane(item.at("where"), context);
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

// One support per side it names (several with "where").
std::vector<analysis::Support> read_support(const Field& item, const Context& context) {
  item.expect_object({"side", "patch", "where", "control_point", "fix", "value", "symmetry"});
  analysis::Support support;
  const int patch = patch_index(item, context);
  std::vector<analysis::Side> sides;
  if (item.has("control_point")) {
    if (item.has("side") || item.has("where"))
      item.fail(
          ": give either \"side\" or \"where\" (every control point of sides) or "
          "\"control_point\", not both");
    support.side.patch = patch;
    support.control_point = read_control_point(item.at("control_point"),
                                               (*context.patches)[static_cast<size_t>(patch)]);
  } else if (item.has("side") || item.has("where")) {
    sides = read_sides(item, context);
  } else {
    item.fail(
        ": give \"side\" (e.g. \"u0\"), \"where\" (e.g. {\"x\": 0}) or \"control_point\" for "
        "this support");
  }
  // The same support on every side named.
  auto on_sides = [&](const analysis::Support& one) {
    if (sides.empty()) return std::vector<analysis::Support>{one};
    std::vector<analysis::Support> all;
    for (const analysis::Side& side : sides) {
      all.push_back(one);
      all.back().side = side;
    }
    return all;
  };

  const bool symmetry = item.has("symmetry") && item.at("symmetry").boolean();
  if (symmetry) {
    if (item.has("fix") || item.has("value"))
      item.fail(
          ": \"symmetry\": true fixes the normal component; do not combine it with "
          "\"fix\" or \"value\"");
    if (support.control_point)
      item.fail(": \"symmetry\" needs a side (its normal), not a single control point");
    support.symmetry = true;
    return on_sides(support);
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
  return on_sides(support);
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

void reject_load_on_fixed_side(const Field& entry, const analysis::Side& side,
                               const std::vector<analysis::Support>& supports,
                               const Context& context) {
  const auto sides = fixed_sides(supports);
  const auto it = sides.find({side.patch, side.dir, side.end});
  if (it == sides.end()) return;
  for (int c = 0; c < context.dimension; ++c)
    if (!it->second[c]) return;
  const Field field = entry.has("side") ? entry.at("side") : entry.at("where");
  field.fail(": side " + std::string(kSideNames[2 * side.dir + side.end]) + " of patch " +
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
      entry.expect_object({"side", "patch", "where", "value"});
      analysis::Traction traction;
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
      for (const analysis::Side& side : read_sides(entry, context)) {
        reject_load_on_fixed_side(entry, side, supports, context);
        traction.side = side;
        load_case.tractions.push_back(traction);
      }
    }
  }
  if (item.has("pressures")) {
    for (const Field& entry : item.at("pressures").elements()) {
      entry.expect_object({"side", "patch", "where", "value"});
      analysis::Pressure pressure;
      pressure.value = entry.at("value").number();
      for (const analysis::Side& side : read_sides(entry, context)) {
        reject_load_on_fixed_side(entry, side, supports, context);
        pressure.side = side;
        load_case.pressures.push_back(pressure);
      }
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
    for (analysis::Support& support : read_support(item, context)) supports.push_back(support);
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
