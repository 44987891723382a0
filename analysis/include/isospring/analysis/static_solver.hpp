#pragma once
// Linear static solve of all load cases with one factorisation.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "isospring/analysis/constraints.hpp"
#include "isospring/analysis/dof_map.hpp"
#include "isospring/analysis/problem.hpp"

namespace isospring::analysis {

struct SolverOptions {
  // kAuto: choose_solver on the problem's traits (`analyze --solver auto`, its default). kAmg:
  // CG with PETSc's smoothed-aggregation AMG and the rigid-body near-null space, on this process
  // (solve_static_amg; needs a build with PETSc).
  enum class Method { kCholesky, kConjugateGradient, kAuto, kAmg } method = Method::kCholesky;
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
  double solve_seconds = 0;  // load vector, solve and the results below
  double post_seconds = 0;   // of solve_seconds: K u, reactions, energy, control displacements
  // Iterative solves (kConjugateGradient, kAmg, the PETSc backend): Krylov iterations and the true
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

/// Free DOFs (3D, 2D) up to which kAuto always takes sparse Cholesky. Why
/// (bench/bench_analysis.cpp, docs/performance.md): on the clamped p = 2 cube CHOLMOD's
/// factorisation costs 1.5-3 s CPU at 16,524 free DOFs; below ~20,000 DOFs the direct solve takes a
/// few seconds at most and is immune to the conditioning that slows CG (slender or nearly
/// incompressible parts). In 2D the factor grows as N log N (133,128 DOFs factorise in 4.8 s), so
/// the direct solver stays up to 500,000 DOFs.
inline constexpr double kAutoIterativeDofs3d = 20000;
inline constexpr double kAutoIterativeDofs2d = 500000;

/// What kAuto's rule looks at (solver_problem_traits computes it from a problem).
struct SolverTraits {
  int dimension = 3;     // spatial dimension, 2 or 3
  double free_dofs = 0;  // DOFs without the supported ones
  int load_cases = 1;    // one factorisation serves them all; an iterative solve runs per case
  double poisson = 0.3;  // nu: CG's condition number grows as 1 / (1 - 2 nu)
  double aspect = 1.0;   // slenderness: the control net's longest / shortest principal extent
  bool amg_available = false;  // this build has PETSc (petsc_available())
};

struct SolverChoice {
  SolverOptions::Method method = SolverOptions::Method::kCholesky;
  std::string reason;
  // The rule's estimates (seconds on the 2-core reference machine; 0 when not estimated).
  double cholesky_seconds = 0, cg_seconds = 0, amg_seconds = 0;
};

/// The traits of `problem`: its dimension, free DOFs, load cases, Poisson ratio and the aspect
/// ratio sqrt(lambda_max / lambda_min) of the covariance of its control points (in 2D, of the
/// in-plane extents), which is the length / thickness of a beam or plate in any orientation.
SolverTraits solver_problem_traits(const Problem& problem, const DofMap& dofs,
                                   const Constraints& constraints);

/// kAuto's rule. Sparse Cholesky up to kAutoIterativeDofs2d / 3d free DOFs. Above, the cheapest
/// of three estimated costs from the traits (static_solver_choice.cpp has the model and the
/// measurements behind its constants): the factorisation plus a solve per load case, block-Jacobi
/// CG per load case, and AMG-preconditioned CG (when available). `reason` gives the estimates.
SolverChoice choose_solver(const SolverTraits& traits);

/// The rule for a well-conditioned problem (nu 0.3, aspect 1, one load case, no AMG).
SolverChoice choose_solver(int dimension, double free_dofs);

/// Validates the problem, assembles K, applies the supports by elimination and solves every load
/// case. Sparse Cholesky (CHOLMOD supernodal) factorises once for all load cases; conjugate
/// gradients use a nodal block-Jacobi preconditioner (block_cg.hpp). Throws nurbs::InputError for
/// bad input (including supports that leave rigid-body motions free) and std::runtime_error when
/// the factorisation or CG fails.
StaticResult solve_static(const Problem& problem, const SolverOptions& options = {});

}  // namespace isospring::analysis
