#pragma once
// Factorisation of a symmetric tangent stiffness (upper triangle stored): CHOLMOD supernodal LLT,
// or a simplicial LDL^T when the matrix is not positive definite (compressive states of large-
// deformation models can make the tangent indefinite; LDL^T without pivoting still handles the
// usual non-zero pivots). Shared by the nonlinear static solver and the identification's
// nonlinear forward model.
#include <Eigen/CholmodSupport>
#include <Eigen/Core>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <vector>

namespace isospring::analysis {

class TangentSolver {
 public:
  /// False when neither factorisation succeeds or a pivot is zero or not finite (singular).
  bool compute(const Eigen::SparseMatrix<double>& upper);
  /// Solves for one or several right-hand sides (columns).
  Eigen::MatrixXd solve(const Eigen::MatrixXd& rhs) const;

 private:
  // The symbolic analysis (ordering) of a factorisation depends on the pattern only: each is
  // kept for the pattern it was made for, and a matrix with that pattern (a Newton tangent at
  // the next iterate) is factorised numerically only.
  struct Pattern {
    std::vector<int> outer, inner;
    bool same(const Eigen::SparseMatrix<double>& m) const;
    void keep(const Eigen::SparseMatrix<double>& m);
  };
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Upper> llt_;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Upper> ldlt_;
  Pattern llt_pattern_, ldlt_pattern_;
  bool use_llt_ = true;
};

}  // namespace isospring::analysis
