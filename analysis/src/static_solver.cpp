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
#include "static_result.hpp"

namespace isospring::analysis {

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
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

  for (const auto& load : problem.load_cases) {
    start = std::chrono::steady_clock::now();
    const Eigen::VectorXd force = assemble_load(problem, dofs, load);
    detail::check_load_finite(load, force);
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
    Eigen::VectorXd displacement = reduced.expand(free_solution);
    const Eigen::VectorXd internal = stiffness.selfadjointView<Eigen::Upper>() * displacement;
    LoadCaseResult out = detail::load_case_result(problem, dofs, constraints, load, force,
                                                  std::move(displacement), internal);
    out.solve_seconds = seconds_since(start);
    result.load_cases.push_back(std::move(out));
  }
  return result;
}

}  // namespace isospring::analysis
