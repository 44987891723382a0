#pragma once
// Linear static solve of all load cases with one factorisation.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "isospring/analysis/problem.hpp"

namespace isospring::analysis {

struct SolverOptions {
  // kAuto: choose_solver on the problem's size (`analyze --solver auto`, its default).
  enum class Method { kCholesky, kConjugateGradient, kAuto } method = Method::kCholesky;
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
  SolverOptions::Method method = SolverOptions::Method::kCholesky;  // the solver used
  std::string method_reason;  // why kAuto chose it (empty for an explicit method)
  int dofs = 0;               // all DOFs, supported ones included
  double assembly_seconds = 0, factorization_seconds = 0;
  int ranks = 1;               // MPI ranks of the solve (the PETSc backend)
  std::string preconditioner;  // the PETSc backend's Krylov method and preconditioner
};

struct SolverChoice {
  SolverOptions::Method method = SolverOptions::Method::kCholesky;
  std::string reason;
};

/// Free DOFs (3D, 2D) above which kAuto takes block-Jacobi CG instead of sparse Cholesky. Why
/// (bench/bench_analysis.cpp, docs/performance.md): on the clamped p = 2 cube CHOLMOD's
/// factorisation costs 1.5-3 s CPU at 16,524 free DOFs and 55 s at 114,444 (nested-dissection
/// fill grows as N^2 in 3D), CG 0.2 s and 2.8 s; below ~20,000 DOFs the direct solve takes a few
/// seconds at most and is immune to the conditioning that slows CG (slender or nearly
/// incompressible parts), so it is kept there. In 2D the factor grows as N log N (133,128 DOFs
/// factorise in 4.8 s), so the direct solver stays up to 500,000 DOFs.
inline constexpr double kAutoIterativeDofs3d = 20000;
inline constexpr double kAutoIterativeDofs2d = 500000;

/// kAuto's rule: sparse Cholesky up to the threshold of the spatial dimension (2 or 3), CG
/// above; `reason` says which threshold decided.
SolverChoice choose_solver(int dimension, double free_dofs);

/// Validates the problem, assembles K, applies the supports by elimination and solves every load
/// case. Sparse Cholesky (CHOLMOD supernodal) factorises once for all load cases; conjugate
/// gradients use a nodal block-Jacobi preconditioner (block_cg.hpp). Throws nurbs::InputError for
/// bad input (including supports that leave rigid-body motions free) and std::runtime_error when
/// the factorisation or CG fails.
StaticResult solve_static(const Problem& problem, const SolverOptions& options = {});

}  // namespace isospring::analysis
