#pragma once
// Elimination of prescribed DOFs: K_ff u_f = f_f - K_fc u_c on the free DOFs.
#include <Eigen/Sparse>

#include "isospring/analysis/constraints.hpp"

namespace isospring::analysis::detail {

struct ReducedSystem {
  /// `matrix` is an upper-triangular symmetric matrix.
  ReducedSystem(const Eigen::SparseMatrix<double>& matrix, const Constraints& constraints);

  Eigen::SparseMatrix<double> free_matrix;  // upper triangle of K_ff
  std::vector<int> free_index;              // global DOF -> free index, -1 when prescribed
  std::vector<int> free_dofs;               // free index -> global DOF
  Eigen::VectorXd prescribed;               // global vector with the prescribed values, 0 elsewhere
  Eigen::VectorXd coupling;                 // K * prescribed (global)

  /// f_f - K_fc u_c.
  Eigen::VectorXd free_rhs(const Eigen::VectorXd& force) const;
  /// Global vector from the free solution and the prescribed values.
  Eigen::VectorXd expand(const Eigen::VectorXd& free_solution) const;
};

}  // namespace isospring::analysis::detail
