// Problem validation.
#include "isospring/analysis/validation.hpp"

#include <set>

#include "isospring/analysis/elasticity.hpp"
#include "isospring/analysis/sides.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::analysis {

namespace {

void check_side(const Problem& problem, const Side& side, const std::string& where) {
  const int patches = static_cast<int>(problem.patches.size());
  if (side.patch < 0 || side.patch >= patches)
    throw nurbs::InputError(where + ": patch " + std::to_string(side.patch) +
                            " does not exist (the model has " + std::to_string(patches) +
                            " patches, numbered from 0)");
  const int dim = problem.patches[static_cast<size_t>(side.patch)].param_dim();
  if (side.dir < 0 || side.dir >= dim || side.end < 0 || side.end > 1)
    throw nurbs::InputError(where + ": side " +
                            (side.dir >= 0 && side.dir < 3 && side.end >= 0 && side.end <= 1
                                 ? side_name(side)
                                 : std::string("(dir ") + std::to_string(side.dir) + ", end " +
                                       std::to_string(side.end) + ")") +
                            " does not exist on patch " + std::to_string(side.patch) +
                            " of parametric dimension " + std::to_string(dim) +
                            (dim == 2 ? "; use u0 u1 v0 v1" : "; use u0 u1 v0 v1 w0 w1"));
}

void check_control_point(const Problem& problem, int patch, int control_point,
                         const std::string& where) {
  const int count = problem.patches[static_cast<size_t>(patch)].num_points();
  if (control_point < 0 || control_point >= count)
    throw nurbs::InputError(where + ": control point " + std::to_string(control_point) +
                            " does not exist on patch " + std::to_string(patch) + " (it has " +
                            std::to_string(count) + ", numbered from 0, u fastest)");
}

// A side whose every control point has all components fixed by constant/function supports.
bool side_fully_fixed(const Problem& problem, const Side& side) {
  const int dim = problem.formulation == Formulation::kSolid ? 3 : 2;
  const auto& patch = problem.patches[static_cast<size_t>(side.patch)];
  std::set<std::pair<int, int>> fixed;  // (control point, component)
  for (const auto& support : problem.supports) {
    if (support.side.patch != side.patch) continue;
    std::vector<int> points = support.control_point
                                  ? std::vector<int>{*support.control_point}
                                  : side_control_points(patch, support.side.dir, support.side.end);
    for (int p : points)
      for (int c = 0; c < dim; ++c)
        if (support.fixed[static_cast<size_t>(c)]) fixed.insert({p, c});
  }
  for (int p : side_control_points(patch, side.dir, side.end))
    for (int c = 0; c < dim; ++c)
      if (!fixed.count({p, c})) return false;
  return true;
}

}  // namespace

void validate_problem(const Problem& problem, const ValidationOptions& options) {
  check_material(problem.material, problem.formulation);
  if (options.require_density && !(problem.material.density > 0.0))
    throw nurbs::InputError("material.density is " + std::to_string(problem.material.density) +
                            ": mass matrices and eigenmodes need a positive density [kg/m^3]");
  if (problem.patches.empty())
    throw nurbs::InputError("the problem has no patches: give at least one NURBS patch");
  if (problem.quadrature_points < 0 || problem.quadrature_points > 30)
    throw nurbs::InputError("quadrature_points is " + std::to_string(problem.quadrature_points) +
                            ": use 0 (degree + 1 per direction) or 1..30");
  const bool solid = problem.formulation == Formulation::kSolid;
  for (size_t p = 0; p < problem.patches.size(); ++p) {
    const auto& patch = problem.patches[p];
    const std::string where = "patch " + std::to_string(p);
    if (solid && patch.param_dim() != 3)
      throw nurbs::InputError(where + " has parametric dimension " +
                              std::to_string(patch.param_dim()) +
                              ": a solid (3D) model needs volume patches (u, v, w)");
    if (!solid && patch.param_dim() != 2)
      throw nurbs::InputError(where + " has parametric dimension " +
                              std::to_string(patch.param_dim()) +
                              ": a plane stress/strain model needs surface patches (u, v)");
    if (!solid)
      for (int i = 0; i < patch.num_points(); ++i)
        if (patch.control_point(i).z() != 0.0)
          throw nurbs::InputError(where + ", control point " + std::to_string(i) +
                                  " has z = " + std::to_string(patch.control_point(i).z()) +
                                  ": plane models lie in the xy-plane; set z = 0");
  }
  for (size_t s = 0; s < problem.supports.size(); ++s) {
    const auto& support = problem.supports[s];
    const std::string where = "supports[" + std::to_string(s) + "]";
    check_side(problem, support.side, where);
    if (support.control_point)
      check_control_point(problem, support.side.patch, *support.control_point, where);
    if (!support.symmetry && !support.fixed[0] && !support.fixed[1] && !support.fixed[2])
      throw nurbs::InputError(where +
                              " fixes no displacement component: set `fixed` for at "
                              "least one of x, y, z or make it a symmetry support");
    if (!support.value.allFinite()) throw nurbs::InputError(where + ".value is not finite");
  }
  if (options.require_load_cases && problem.load_cases.empty())
    throw nurbs::InputError(
        "the problem has no load cases: add at least one (tractions, "
        "pressures, point loads, body force or gravity)");
  std::set<std::string> ids;
  for (size_t l = 0; l < problem.load_cases.size(); ++l) {
    const auto& load = problem.load_cases[l];
    const std::string where = "load case \"" + load.id + "\"";
    if (!ids.insert(load.id).second)
      throw nurbs::InputError(where + " appears twice: give each load case a unique id");
    auto check_loaded_side = [&](const Side& side, const std::string& what) {
      check_side(problem, side, where + ", " + what);
      if (side_fully_fixed(problem, side))
        throw nurbs::InputError(where + ", " + what + " on patch " + std::to_string(side.patch) +
                                ", side " + side_name(side) +
                                ": every displacement component of this side is fixed, so the "
                                "load would only produce reactions; load a free side instead");
    };
    for (const auto& traction : load.tractions) check_loaded_side(traction.side, "traction");
    for (const auto& pressure : load.pressures) check_loaded_side(pressure.side, "pressure");
    for (const auto& point_load : load.point_loads) {
      check_side(problem, Side{point_load.patch, 0, 0}, where + ", point load");
      check_control_point(problem, point_load.patch, point_load.control_point,
                          where + ", point load");
    }
    if (!load.body_force.allFinite() || !load.gravity.allFinite())
      throw nurbs::InputError(where + ": body_force/gravity must be finite");
  }
}

}  // namespace isospring::analysis
