// Per-load-case results of a static solve (static_result.hpp).
#include "static_result.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace isospring::analysis::detail {

namespace {

// A load or material value near the limits of a double (a traction of 1e308 Pa, E = 1e-300)
// makes the loads or the solution overflow; reporting the overflow is better than writing
// inf/NaN (or JSON null) into the results. std::runtime_error: exit status 3.
void check_finite(const std::string& load_case, const std::string& what, bool finite,
                  const std::string& hint) {
  if (!finite)
    throw std::runtime_error("load case '" + load_case + "': " + what +
                             " overflowed (not finite); " + hint);
}

}  // namespace

void check_load_finite(const LoadCase& load, const Eigen::VectorXd& force) {
  check_finite(load.id, "the load vector", force.allFinite(),
               "a traction, pressure, point load, body force or density x gravity is too large "
               "for a double; check the values and their units (SI)");
}

LoadCaseResult load_case_result(const Problem& problem, const DofMap& dofs,
                                const Constraints& constraints, const LoadCase& load,
                                const Eigen::VectorXd& force, Eigen::VectorXd displacement,
                                const Eigen::VectorXd& internal) {
  const int dim = dofs.dofs_per_node();
  LoadCaseResult out;
  out.id = load.id;
  out.displacement = std::move(displacement);
  out.strain_energy = 0.5 * out.displacement.dot(internal);
  for (int d : constraints.dofs) out.reaction_sum[d % dim] += internal[d] - force[d];
  out.control_displacements.resize(problem.patches.size());
  for (size_t p = 0; p < problem.patches.size(); ++p) {
    auto& u = out.control_displacements[p];
    u.assign(static_cast<size_t>(problem.patches[p].num_points()), Eigen::Vector3d::Zero());
    for (size_t i = 0; i < u.size(); ++i) {
      for (int c = 0; c < dim; ++c)
        u[i][c] = out.displacement[dofs.dof(static_cast<int>(p), static_cast<int>(i), c)];
      out.max_displacement = std::max(out.max_displacement, u[i].norm());
    }
  }
  std::ostringstream modulus;
  modulus << problem.material.youngs_modulus;
  const std::string hint = "the loads are too large for the stiffness (E = " + modulus.str() +
                           " Pa); check E and the loads and their units (SI)";
  check_finite(load.id, "the displacements", out.displacement.allFinite(), hint);
  check_finite(load.id, "the largest displacement", std::isfinite(out.max_displacement), hint);
  check_finite(load.id, "the strain energy", std::isfinite(out.strain_energy), hint);
  check_finite(load.id, "the reaction sum", out.reaction_sum.allFinite(), hint);
  return out;
}

}  // namespace isospring::analysis::detail
