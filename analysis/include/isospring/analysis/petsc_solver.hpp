#pragma once
// The distributed backend of the linear static solve: PETSc with MPI (`mpirun -np N isospring
// analyze CASE --backend petsc`). Every rank builds the same problem (geometry and DOF numbering
// are small next to K); the elements are split into N contiguous ranges, each rank assembles its
// own into a PETSc MPIAIJ matrix (block size = dimension) with the same element kernel as
// assemble_stiffness, and conjugate gradients with smoothed-aggregation AMG (GAMG, the rigid-body
// modes as near-null space) solve every load case. Supports are the same prescribed DOFs as the
// serial solver (build_constraints), multipatch interfaces the same shared nodes (DofMap).
//
// The backend is optional at build time (CMake ISOSPRING_WITH_PETSC); petsc_available() tells.
#include <functional>
#include <string>

#include "isospring/analysis/problem.hpp"
#include "isospring/analysis/static_solver.hpp"

namespace isospring::analysis {

/// True when this build has the PETSc backend.
bool petsc_available();

/// PETSc (and MPI, when PETSc starts it) initialised for the lifetime of the object, so a
/// program initialises MPI only when it uses the backend: a serial run needs no mpirun and no
/// MPI at run time. PETSc options come from the PETSC_OPTIONS environment variable (e.g.
/// "-ksp_monitor -pc_type hypre"). Throws nurbs::InputError when the build has no PETSc (the
/// message names the packages and the CMake option).
class PetscSession {
 public:
  PetscSession();
  ~PetscSession();
  PetscSession(const PetscSession&) = delete;
  PetscSession& operator=(const PetscSession&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }

  /// Collective: runs `step` on rank 0 only (checks of the output folder, say) and, when it
  /// throws, makes every rank throw the same (nurbs::InputError stays one, anything else becomes
  /// std::runtime_error), so that the other ranks do not wait for rank 0 forever.
  void on_root(const std::function<void()>& step) const;

 private:
  bool finalize_ = false;  // false when PETSc was initialised before this object
  int rank_ = 0;
  int size_ = 1;
};

struct PetscSolverOptions {
  /// Stop when the true (unpreconditioned) residual ||b - K u|| <= tolerance ||b||. 1e-12 keeps
  /// the displacements within ~1e-9 relative of the direct solver on the shipped cases.
  double relative_tolerance = 1e-12;
  int max_iterations = 20000;
  /// "gamg": PETSc's smoothed aggregation with the rigid-body near-null space (default);
  /// "hypre": hypre BoomerAMG (scalar, no near-null space); "lu": MUMPS direct (parallel LU,
  /// for checks). PETSC_OPTIONS overrides any of it.
  std::string preconditioner = "gamg";
  /// OpenMP threads per rank (assembly of the load vectors); 1: one rank per core.
  int threads = 1;
};

/// The same solve and results as solve_static, distributed over the ranks of PETSC_COMM_WORLD.
/// Collective: every rank calls it with the same problem. The full result (displacements,
/// strain energies, reaction sums) is on rank 0; the other ranks get the load-case ids, the
/// iteration counts and residuals. Needs a live PetscSession. Throws nurbs::InputError for bad
/// input (on every rank, with the message of the rank that found it) and std::runtime_error when
/// the Krylov solve does not converge.
StaticResult solve_static_petsc(const Problem& problem, const PetscSolverOptions& options = {});

/// The same solve on this process alone (PETSC_COMM_SELF; not collective, no mpirun): the serial
/// algebraic-multigrid solver of solve_static (SolverOptions::Method::kAmg). Starts PETSc (and MPI
/// as a singleton) at its first call and keeps it until the program ends. Throws
/// nurbs::InputError when the build has no PETSc.
StaticResult solve_static_amg(const Problem& problem, const PetscSolverOptions& options = {});

}  // namespace isospring::analysis
