#pragma once
// What a static solve reports per load case, from the displacement and K u: shared by the serial
// solver (static_solver.cpp) and the PETSc backend (petsc_solver.cpp), so both report the same
// quantities the same way.
#include <Eigen/Core>

#include "isospring/analysis/constraints.hpp"
#include "isospring/analysis/static_solver.hpp"

namespace isospring::analysis::detail {

/// Throws std::runtime_error when the load vector of `load` is not finite.
void check_load_finite(const LoadCase& load, const Eigen::VectorXd& force);

/// The result of one load case: `displacement` and `internal` = K u are global DOF vectors in
/// the numbering of `dofs`. Strain energy 1/2 u.K u, reaction sums (K u - f over the supported
/// DOFs), control-point displacements and the largest; throws std::runtime_error when one of
/// them overflowed. solve_seconds is left to the caller.
LoadCaseResult load_case_result(const Problem& problem, const DofMap& dofs,
                                const Constraints& constraints, const LoadCase& load,
                                const Eigen::VectorXd& force, Eigen::VectorXd displacement,
                                const Eigen::VectorXd& internal);

}  // namespace isospring::analysis::detail
