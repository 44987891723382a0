#include "isospring/analysis/tangent_solver.hpp"

namespace isospring::analysis {

bool TangentSolver::compute(const Eigen::SparseMatrix<double>& upper) {
  llt_.cholmod().print = 0;  // an indefinite tangent is handled below, not printed
  llt_.compute(upper);
  use_llt_ = llt_.info() == Eigen::Success;
  if (use_llt_) return true;
  ldlt_.compute(upper);
  if (ldlt_.info() != Eigen::Success) return false;
  const auto d = ldlt_.vectorD();
  return d.allFinite() && d.cwiseAbs().minCoeff() > 0.0;
}

Eigen::MatrixXd TangentSolver::solve(const Eigen::MatrixXd& rhs) const {
  return use_llt_ ? Eigen::MatrixXd(llt_.solve(rhs)) : Eigen::MatrixXd(ldlt_.solve(rhs));
}

}  // namespace isospring::analysis
