// Static solve: assembly, elimination of supported DOFs, one factorisation, all load cases.
#include "isospring/analysis/static_solver.hpp"

#include <omp.h>

#include <Eigen/CholmodSupport>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/block_cg.hpp"
#include "isospring/analysis/constraints.hpp"
#include "isospring/analysis/petsc_solver.hpp"
#include "isospring/analysis/thread_scope.hpp"
#include "reduced_system.hpp"
#include "static_result.hpp"

namespace isospring::analysis {

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Sparse Cholesky (CHOLMOD supernodal) of K_ff, once for all load cases.
void solve_direct(const Problem& problem, const DofMap& dofs, const Constraints& constraints,
                  const Eigen::SparseMatrix<double>& stiffness, StaticResult& result) {
  const detail::ReducedSystem reduced(stiffness, constraints);
  auto start = std::chrono::steady_clock::now();
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Upper> cholesky;
  cholesky.compute(reduced.free_matrix);
  if (cholesky.info() != Eigen::Success)
    throw std::runtime_error(
        "the stiffness matrix could not be factorised (it is not positive definite): the "
        "model may have parts not held by supports or patches that do not connect");
  result.factorization_seconds = seconds_since(start);
  for (const auto& load : problem.load_cases) {
    start = std::chrono::steady_clock::now();
    const Eigen::VectorXd force = assemble_load(problem, dofs, load);
    detail::check_load_finite(load, force);
    Eigen::VectorXd displacement = reduced.expand(cholesky.solve(reduced.free_rhs(force)));
    const auto post_start = std::chrono::steady_clock::now();
    const Eigen::VectorXd internal = stiffness.selfadjointView<Eigen::Upper>() * displacement;
    LoadCaseResult out = detail::load_case_result(problem, dofs, constraints, load, force,
                                                  std::move(displacement), internal);
    out.post_seconds = seconds_since(post_start);
    out.solve_seconds = seconds_since(start);
    result.load_cases.push_back(std::move(out));
  }
}

// Block-Jacobi conjugate gradients (block_cg.hpp) on K with the supported DOFs' rows and
// columns replaced by the identity: the system keeps its node blocks, and no reduced copy of K is
// made. Why not incomplete Cholesky (what this was before): on the clamped 32^3 cube its
// factor alone took longer than the whole block-Jacobi solve, for 114 instead of 189 iterations
// (docs/performance.md).
void solve_iterative(const Problem& problem, const DofMap& dofs, const Constraints& constraints,
                     const Eigen::SparseMatrix<double>& stiffness, const SolverOptions& options,
                     StaticResult& result) {
  auto start = std::chrono::steady_clock::now();
  std::vector<bool> fixed(static_cast<size_t>(stiffness.rows()), false);
  Eigen::VectorXd prescribed = Eigen::VectorXd::Zero(stiffness.rows());
  for (size_t k = 0; k < constraints.dofs.size(); ++k) {
    fixed[static_cast<size_t>(constraints.dofs[k])] = true;
    prescribed[constraints.dofs[k]] = constraints.values[k];
  }
  const Eigen::VectorXd coupling = stiffness.selfadjointView<Eigen::Upper>() * prescribed;
  const SymmetricBlockMatrix matrix(stiffness, dofs.dofs_per_node(), fixed);
  result.factorization_seconds = seconds_since(start);
  BlockCgOptions cg;
  cg.tolerance = options.cg_tolerance;
  for (const auto& load : problem.load_cases) {
    start = std::chrono::steady_clock::now();
    const Eigen::VectorXd force = assemble_load(problem, dofs, load);
    detail::check_load_finite(load, force);
    Eigen::VectorXd rhs = force - coupling;
    for (size_t k = 0; k < fixed.size(); ++k)
      if (fixed[k]) rhs[static_cast<Eigen::Index>(k)] = 0;
    Eigen::VectorXd solution;
    const BlockCgResult cg_result = block_cg(matrix, rhs, solution, cg);
    if (!cg_result.converged)
      throw std::runtime_error(
          "conjugate gradients did not converge for load case \"" + load.id + "\" in " +
          std::to_string(cg_result.iterations) + " iterations (residual " +
          std::to_string(cg_result.relative_residual) + "); use the Cholesky solver");
    Eigen::VectorXd displacement = solution + prescribed;
    const auto post_start = std::chrono::steady_clock::now();
    const Eigen::VectorXd internal = stiffness.selfadjointView<Eigen::Upper>() * displacement;
    LoadCaseResult out = detail::load_case_result(problem, dofs, constraints, load, force,
                                                  std::move(displacement), internal);
    out.post_seconds = seconds_since(post_start);
    out.iterations = cg_result.iterations;
    // The true residual of the system solved, as the PETSc backend reports it.
    const double rhs_norm = rhs.norm();
    Eigen::VectorXd check;
    matrix.multiply(solution, check);
    out.relative_residual = rhs_norm > 0 ? (rhs - check).norm() / rhs_norm : 0.0;
    out.solve_seconds = seconds_since(start);
    result.load_cases.push_back(std::move(out));
  }
}

}  // namespace

StaticResult solve_static(const Problem& problem, const SolverOptions& options) {
  const ThreadScope threads(options.threads);
  const SupportedProblem supported = number_and_support(problem);
  const DofMap& dofs = supported.dofs;
  const Constraints& constraints = supported.constraints;

  SolverOptions::Method method = options.method;
  std::string reason;
  if (method == SolverOptions::Method::kAuto) {
    const SolverChoice choice = choose_solver(solver_problem_traits(problem, dofs, constraints));
    method = choice.method;
    reason = choice.reason;
  }
  if (method == SolverOptions::Method::kAmg) {
    // PETSc's smoothed aggregation on this process (petsc_solver.hpp), which assembles its own
    // matrix; the same results and the same stopping rule as CG.
    PetscSolverOptions amg;
    amg.preconditioner = "gamg";
    amg.relative_tolerance = options.cg_tolerance;
    amg.threads = options.threads;
    StaticResult result = solve_static_amg(problem, amg);
    result.method = method;
    result.method_reason = reason;
    return result;
  }

  StaticResult result;
  result.dofs = dofs.num_dofs();
  result.method = method;
  result.method_reason = reason;
  auto start = std::chrono::steady_clock::now();
  const Eigen::SparseMatrix<double> stiffness = assemble_stiffness(problem, dofs);
  result.assembly_seconds = seconds_since(start);
  if (result.method == SolverOptions::Method::kConjugateGradient)
    solve_iterative(problem, dofs, constraints, stiffness, options, result);
  else
    solve_direct(problem, dofs, constraints, stiffness, result);
  return result;
}

}  // namespace isospring::analysis
