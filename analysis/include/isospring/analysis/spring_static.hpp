#pragma once
// Static equilibrium of a spring network: linear (K at rest) and nonlinear (Newton on the exact
// spring forces). Fixed particles do not move; forces are flat vectors (spring_mechanics.hpp).
#include <Eigen/Core>
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <vector>

#include "isospring/analysis/spring_network.hpp"

namespace isospring::analysis {

/// The DOFs a solve works on: all except `constrained` (which stay at zero displacement).
class FreeDofSet {
 public:
  FreeDofSet(int num_dofs, const std::vector<int>& constrained);
  int num_free() const { return static_cast<int>(free_.size()); }
  int num_dofs() const { return static_cast<int>(index_.size()); }
  const std::vector<int>& free_dofs() const { return free_; }
  /// Global DOF -> free index, -1 when constrained.
  int free_index(int dof) const { return index_[static_cast<size_t>(dof)]; }
  Eigen::SparseMatrix<double> restrict(const Eigen::SparseMatrix<double>& matrix) const;
  Eigen::VectorXd restrict(const Eigen::VectorXd& vector) const;
  /// Global vector with zeros on constrained DOFs.
  Eigen::VectorXd expand(const Eigen::VectorXd& free_vector) const;

 private:
  std::vector<int> free_;
  std::vector<int> index_;
};

struct SpringSolveOptions {
  int max_iterations = 50;   // Newton iterations per load step
  double tolerance = 1e-10;  // on |residual| / |external force|
  int load_steps = 1;        // the load is applied in equal increments
};

struct SpringSolveResult {
  Eigen::VectorXd displacement;  // flat, zero on fixed particles
  int iterations = 0;            // Newton iterations in total (1 for the linear solve)
  double relative_residual = 0;  // |f_ext + f_int| / |f_ext| on the free DOFs at the end
  bool converged = false;
};

/// Constrained DOFs of a solve: the components of the fixed particles plus `extra` (single
/// components held at zero, e.g. symmetry planes), sorted and unique.
std::vector<int> constrained_dofs(const SpringNetwork& network, const std::vector<int>& extra);

/// u = K_rest^-1 f on the free DOFs (`extra_constrained`: see constrained_dofs). Throws
/// std::runtime_error when K is singular (a mechanism: the fixed particles and springs do not
/// hold the network in place).
SpringSolveResult solve_spring_linear(const SpringNetwork& network, const Eigen::VectorXd& force,
                                      const std::vector<int>& extra_constrained = {});

/// solve_spring_linear for many loads on one network: K_rest restricted to the free DOFs is
/// assembled and factorised once (a strain-point model's K takes seconds to assemble), then each
/// solve is solve_spring_linear's, operation for operation. Throws like solve_spring_linear on
/// construction.
class SpringLinearSolver {
 public:
  explicit SpringLinearSolver(const SpringNetwork& network,
                              const std::vector<int>& extra_constrained = {});
  /// `force`: flat, one entry per particle component.
  SpringSolveResult solve(const Eigen::VectorXd& force) const;

 private:
  FreeDofSet dofs_;
  Eigen::SparseMatrix<double> k_;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver_;
};

/// Newton's method with the analytic tangent stiffness and a backtracking line search, starting
/// from the linear solution of the first load step. `converged` is false when the tolerance is not
/// reached; the caller decides whether that is an error.
SpringSolveResult solve_spring_newton(const SpringNetwork& network, const Eigen::VectorXd& force,
                                      const SpringSolveOptions& options = {},
                                      const std::vector<int>& extra_constrained = {});

}  // namespace isospring::analysis
