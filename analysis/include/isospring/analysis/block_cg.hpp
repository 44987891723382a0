#pragma once
// Conjugate gradients with a (nodal block) Jacobi preconditioner on a symmetric matrix stored
// once, as the upper triangle in d x d node blocks (d = DOFs per node, 2 or 3).
//
// Why not Eigen's ConjugateGradient: with the upper triangle only (half the memory traffic), its
// product `selfadjointView<Upper>() * x` runs on one thread; with both triangles in row-major
// storage it runs on all threads but reads twice the matrix. The product here reads each stored
// block once and uses every thread: each thread adds the transposed contributions of its block
// columns into a private vector, summed at the end. Node blocks also store one column index per
// 9 values instead of one per value. CG is bound by that product: measured on the clamped p = 2
// cube, docs/performance.md, bench/bench_analysis.cpp BM_Iterative*.
//
// Why (block) Jacobi and not incomplete Cholesky: building the incomplete factor of the 32^3 cube
// took longer than the whole block-Jacobi solve, and its triangular solves are sequential.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

namespace isospring::analysis {

class SymmetricBlockMatrix {
 public:
  /// `upper`: the upper triangle (column-major, as assemble_stiffness returns it) of a symmetric
  /// matrix whose DOF k belongs to node k / block_size. DOFs with fixed[k] (empty: none) get a
  /// zero row and column and a unit diagonal, so that the system keeps its node blocks; their
  /// right-hand side must be 0 and so is their solution.
  SymmetricBlockMatrix(const Eigen::SparseMatrix<double>& upper, int block_size,
                       const std::vector<bool>& fixed = {});

  Eigen::Index rows() const { return rows_; }
  int block_size() const { return block_size_; }
  /// Stored blocks (upper triangle, diagonal included).
  Eigen::Index stored_blocks() const { return static_cast<Eigen::Index>(block_row_.size()); }
  /// Blocks with different values (bitwise). When at most one stored block in eight is distinct
  /// (structured meshes: the 32^3 p = 2 cube has 9,557 for 2.5 M), each stored block keeps an
  /// index into a table of the distinct ones: the product then reads 8 instead of 76 bytes per
  /// block and is no longer bound by memory bandwidth. The values, and so every product, are
  /// exactly those of the plain storage.
  Eigen::Index distinct_blocks() const {
    return static_cast<Eigen::Index>(values_.size()) / (block_size_ * block_size_);
  }

  /// y = A x with all OpenMP threads. Not reentrant (uses per-thread scratch vectors).
  void multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const;

  /// Diagonal block of node `block` (d x d, symmetric).
  Eigen::MatrixXd diagonal_block(Eigen::Index block) const;

 private:
  template <int D, bool Shared>
  void multiply_fixed(const Eigen::VectorXd& x, Eigen::VectorXd& y) const;
  template <int D>
  void multiply_block_size(const Eigen::VectorXd& x, Eigen::VectorXd& y) const;
  void share_repeated_blocks();
  const double* block_values(Eigen::Index block) const {
    const Eigen::Index at = block_value_.empty() ? block : block_value_[static_cast<size_t>(block)];
    return values_.data() + at * block_size_ * block_size_;
  }

  Eigen::Index rows_ = 0;
  int block_size_ = 3;
  // Block compressed columns: blocks of block column J are column_start_[J] .. [J + 1]; each
  // holds its block row and d * d values (column-major). Diagonal blocks are stored full.
  std::vector<Eigen::Index> column_start_;
  std::vector<int> block_row_;
  std::vector<double> values_;    // per stored block, or the table of distinct blocks
  std::vector<int> block_value_;  // empty, or each stored block's index into the table
  mutable std::vector<Eigen::VectorXd> scratch_;
};

struct BlockCgOptions {
  enum class Preconditioner { kJacobi, kBlockJacobi } preconditioner = Preconditioner::kBlockJacobi;
  double tolerance = 1e-10;  // on ||b - A x|| / ||b||, as Eigen's ConjugateGradient
  int max_iterations = 0;    // 0: 10 x rows, at least 1000
};

struct BlockCgResult {
  int iterations = 0;
  double relative_residual = 0;  // the recurrence's ||r|| / ||b|| at exit
  bool converged = false;
};

/// Solves A x = b from x = 0.
BlockCgResult block_cg(const SymmetricBlockMatrix& matrix, const Eigen::VectorXd& rhs,
                       Eigen::VectorXd& solution, const BlockCgOptions& options = {});

}  // namespace isospring::analysis
