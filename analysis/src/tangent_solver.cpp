#include "isospring/analysis/tangent_solver.hpp"

#include <algorithm>

namespace isospring::analysis {

bool TangentSolver::Pattern::same(const Eigen::SparseMatrix<double>& m) const {
  const auto n = static_cast<size_t>(m.outerSize());
  const auto nnz = static_cast<size_t>(m.nonZeros());
  return m.isCompressed() && outer.size() == n + 1 && inner.size() == nnz &&
         std::equal(outer.begin(), outer.end(), m.outerIndexPtr()) &&
         std::equal(inner.begin(), inner.end(), m.innerIndexPtr());
}

void TangentSolver::Pattern::keep(const Eigen::SparseMatrix<double>& m) {
  if (!m.isCompressed()) {
    outer.clear(), inner.clear();
    return;
  }
  outer.assign(m.outerIndexPtr(), m.outerIndexPtr() + m.outerSize() + 1);
  inner.assign(m.innerIndexPtr(), m.innerIndexPtr() + m.nonZeros());
}

bool TangentSolver::compute(const Eigen::SparseMatrix<double>& upper) {
  llt_.cholmod().print = 0;  // an indefinite tangent is handled below, not printed
  if (!llt_pattern_.same(upper)) {
    llt_.analyzePattern(upper);
    llt_pattern_.keep(upper);
  }
  llt_.factorize(upper);
  use_llt_ = llt_.info() == Eigen::Success;
  if (use_llt_) return true;
  if (!ldlt_pattern_.same(upper)) {
    ldlt_.analyzePattern(upper);
    ldlt_pattern_.keep(upper);
  }
  ldlt_.factorize(upper);
  if (ldlt_.info() != Eigen::Success) return false;
  const auto d = ldlt_.vectorD();
  return d.allFinite() && d.cwiseAbs().minCoeff() > 0.0;
}

Eigen::MatrixXd TangentSolver::solve(const Eigen::MatrixXd& rhs) const {
  return use_llt_ ? Eigen::MatrixXd(llt_.solve(rhs)) : Eigen::MatrixXd(ldlt_.solve(rhs));
}

}  // namespace isospring::analysis
