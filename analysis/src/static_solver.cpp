// Static solve: assembly, elimination of supported DOFs, one factorisation, all load cases.
#include "isospring/analysis/static_solver.hpp"

#include <omp.h>

#include <Eigen/CholmodSupport>
#include <Eigen/IterativeLinearSolvers>
#include <chrono>
#include <cmath>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>

#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/constraints.hpp"
#include "isospring/analysis/thread_scope.hpp"
#include "isospring/analysis/validation.hpp"
#include "reduced_system.hpp"

namespace isospring::analysis {

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

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

StaticResult solve_static(const Problem& problem, const SolverOptions& options) {
  validate_problem(problem);
  const ThreadScope threads(options.threads);
  const DofMap dofs(problem);
  const Constraints constraints = build_constraints(problem, dofs);
  check_rigid_body_modes(problem, dofs, constraints);

  StaticResult result;
  result.dofs = dofs.num_dofs();
  auto start = std::chrono::steady_clock::now();
  const Eigen::SparseMatrix<double> stiffness = assemble_stiffness(problem, dofs);
  result.assembly_seconds = seconds_since(start);

  const detail::ReducedSystem reduced(stiffness, constraints);
  start = std::chrono::steady_clock::now();
  using Cholesky = Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Upper>;
  using CG = Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Upper,
                                      Eigen::IncompleteCholesky<double, Eigen::Upper>>;
  std::unique_ptr<Cholesky> cholesky;
  std::unique_ptr<CG> cg;
  if (options.method == SolverOptions::Method::kCholesky) {
    cholesky = std::make_unique<Cholesky>();
    cholesky->compute(reduced.free_matrix);
    if (cholesky->info() != Eigen::Success)
      throw std::runtime_error(
          "the stiffness matrix could not be factorised (it is not positive definite): the "
          "model may have parts not held by supports or patches that do not connect");
  } else {
    cg = std::make_unique<CG>();
    cg->setTolerance(options.cg_tolerance);
    cg->setMaxIterations(std::max<Eigen::Index>(1000, 10 * reduced.free_matrix.rows()));
    cg->compute(reduced.free_matrix);
    if (cg->info() != Eigen::Success)
      throw std::runtime_error("the incomplete Cholesky preconditioner failed");
  }
  result.factorization_seconds = seconds_since(start);

  const int dim = dofs.dofs_per_node();
  for (const auto& load : problem.load_cases) {
    start = std::chrono::steady_clock::now();
    LoadCaseResult out;
    out.id = load.id;
    const Eigen::VectorXd force = assemble_load(problem, dofs, load);
    check_finite(load.id, "the load vector", force.allFinite(),
                 "a traction, pressure, point load, body force or density x gravity is too large "
                 "for a double; check the values and their units (SI)");
    const Eigen::VectorXd rhs = reduced.free_rhs(force);
    Eigen::VectorXd free_solution;
    if (cholesky) {
      free_solution = cholesky->solve(rhs);
    } else {
      free_solution = cg->solve(rhs);
      if (cg->info() != Eigen::Success)
        throw std::runtime_error("conjugate gradients did not converge for load case \"" + load.id +
                                 "\" in " + std::to_string(cg->iterations()) +
                                 " iterations (residual " + std::to_string(cg->error()) +
                                 "); use the Cholesky solver");
    }
    out.displacement = reduced.expand(free_solution);
    const Eigen::VectorXd internal = stiffness.selfadjointView<Eigen::Upper>() * out.displacement;
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
    out.solve_seconds = seconds_since(start);
    result.load_cases.push_back(std::move(out));
  }
  return result;
}

}  // namespace isospring::analysis
