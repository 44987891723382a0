#pragma once
// Linear static solve of all load cases with one factorisation.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "isospring/analysis/problem.hpp"

namespace isospring::analysis {

struct SolverOptions {
  enum class Method { kCholesky, kConjugateGradient } method = Method::kCholesky;
  double cg_tolerance = 1e-10;  // ||f - K u|| / ||f|| of CG (free DOFs)
  int threads = 0;              // 0 = all
};

struct LoadCaseResult {
  std::string id;
  Eigen::VectorXd displacement;  // global DOF vector (see DofMap)
  std::vector<std::vector<Eigen::Vector3d>> control_displacements;  // [patch][control point]
  double strain_energy = 0;                                         // 1/2 u^T K u
  Eigen::Vector3d reaction_sum = Eigen::Vector3d::Zero();  // sum of K u - f over supported DOFs
  double max_displacement = 0;                             // max |u| over control points
  double solve_seconds = 0;
  // Iterative solves (kConjugateGradient, the PETSc backend): Krylov iterations and the true
  // relative residual ||b - K u|| / ||b|| of the system solved; 0 for the direct solver.
  int iterations = 0;
  double relative_residual = 0;
};

struct StaticResult {
  std::vector<LoadCaseResult> load_cases;
  int dofs = 0;  // all DOFs, supported ones included
  double assembly_seconds = 0, factorization_seconds = 0;
  int ranks = 1;               // MPI ranks of the solve (the PETSc backend)
  std::string preconditioner;  // the PETSc backend's Krylov method and preconditioner
};

/// Validates the problem, assembles K, applies the supports by elimination and solves every load
/// case. Sparse Cholesky (CHOLMOD supernodal) factorises once for all load cases; conjugate
/// gradients use a nodal block-Jacobi preconditioner (block_cg.hpp). Throws nurbs::InputError for
/// bad input (including supports that leave rigid-body motions free) and std::runtime_error when
/// the factorisation or CG fails.
StaticResult solve_static(const Problem& problem, const SolverOptions& options = {});

}  // namespace isospring::analysis
