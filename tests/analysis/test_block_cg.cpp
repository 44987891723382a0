// SymmetricBlockMatrix and block_cg against dense linear algebra: the threaded product of the
// upper-triangle node-block storage equals the full symmetric product (fixed DOFs become unit
// rows and columns), and both preconditioners solve to the requested residual.
#include <gtest/gtest.h>
#include <omp.h>

#include <Eigen/Dense>
#include <random>

#include "isospring/analysis/block_cg.hpp"
#include "isospring/analysis/thread_scope.hpp"

namespace isospring::analysis {
namespace {

// A random sparse SPD matrix (diagonally dominant) of `nodes` x `block` DOFs, dense copy.
Eigen::MatrixXd random_spd(int nodes, int block, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::uniform_int_distribution<int> coin(0, 4);
  const int n = nodes * block;
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < nodes; ++i)
    for (int j = i; j < nodes; ++j) {
      if (i != j && coin(random) != 0) continue;  // about one node pair in five is coupled
      for (int k = 0; k < block; ++k)
        for (int l = 0; l < block; ++l) {
          const double v = value(random);
          a(i * block + k, j * block + l) += v;
          if (i != j) a(j * block + l, i * block + k) += v;
        }
    }
  a = (0.5 * (a + a.transpose())).eval();
  for (int r = 0; r < n; ++r) a(r, r) = a.row(r).cwiseAbs().sum() + 1.0;
  return a;
}

Eigen::SparseMatrix<double> upper_of(const Eigen::MatrixXd& dense) {
  const Eigen::SparseMatrix<double> full = dense.sparseView();
  return full.triangularView<Eigen::Upper>();
}

// The matrix the solver sees: fixed rows/columns zeroed, unit diagonal.
Eigen::MatrixXd with_fixed(Eigen::MatrixXd a, const std::vector<bool>& fixed) {
  for (int k = 0; k < a.rows(); ++k)
    if (fixed[static_cast<size_t>(k)]) {
      a.row(k).setZero();
      a.col(k).setZero();
      a(k, k) = 1.0;
    }
  return a;
}

// Upper triangle of a random symmetric sparse matrix: each node coupled to `couplings` random
// others, all block entries set.
Eigen::SparseMatrix<double> random_sparse_upper(int nodes, int block, int couplings,
                                                unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::uniform_int_distribution<int> node(0, nodes - 1);
  std::vector<Eigen::Triplet<double>> entries;
  for (int i = 0; i < nodes; ++i)
    for (int c = 0; c <= couplings; ++c) {
      const int j = c == 0 ? i : node(random);
      for (int k = 0; k < block; ++k)
        for (int l = 0; l < block; ++l) {
          const int row = std::min(i, j) * block + (i <= j ? k : l);
          const int col = std::max(i, j) * block + (i <= j ? l : k);
          if (row <= col) entries.emplace_back(row, col, value(random));
        }
    }
  Eigen::SparseMatrix<double> upper(nodes * block, nodes * block);
  upper.setFromTriplets(entries.begin(), entries.end());
  return upper;
}

// Large enough (over 200,000 stored values) for the threaded product; the reference is Eigen's
// symmetric product with the fixed DOFs masked.
TEST(BlockCg, ProductMatchesEigenOnEveryThreadCount) {
  for (int block : {1, 2, 3}) {
    const int nodes = 300000 / (block * block * 8);
    const Eigen::SparseMatrix<double> upper =
        random_sparse_upper(nodes, block, 7, 7u + static_cast<unsigned>(block));
    std::vector<bool> fixed(static_cast<size_t>(upper.rows()), false);
    for (size_t k = 0; k < fixed.size(); k += 7) fixed[k] = true;
    const SymmetricBlockMatrix matrix(upper, block, fixed);
    ASSERT_GT(matrix.stored_blocks() * block * block, 200000);
    const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(upper.rows(), -1.0, 2.0);
    Eigen::VectorXd masked = x;
    for (size_t k = 0; k < fixed.size(); ++k)
      if (fixed[k]) masked[static_cast<Eigen::Index>(k)] = 0;
    Eigen::VectorXd expected = upper.selfadjointView<Eigen::Upper>() * masked;
    for (size_t k = 0; k < fixed.size(); ++k)
      if (fixed[k]) expected[static_cast<Eigen::Index>(k)] = x[static_cast<Eigen::Index>(k)];
    for (int threads : {1, 2, 3}) {
      const ThreadScope scope(threads);
      Eigen::VectorXd y;
      matrix.multiply(x, y);
      EXPECT_LT((y - expected).norm(), 1e-12 * expected.norm())
          << "block " << block << ", threads " << threads;
    }
  }
}

// A matrix of few distinct blocks (a banded node pattern repeating three 3 x 3 blocks, as a
// structured mesh's stiffness does) keeps one table of them; its products on every thread
// count equal Eigen's symmetric product, the fixed DOFs masked, and its diagonal blocks are the
// stored ones. A random matrix keeps every block.
TEST(BlockCg, RepeatedBlocksShareOneTable) {
  const int nodes = 20000, d = 3;
  const Eigen::Matrix3d diagonal =
      (Eigen::Matrix3d() << 9, 1, 0.5, 1, 8, 0.25, 0.5, 0.25, 7).finished();
  const Eigen::Matrix3d near = Eigen::Matrix3d::Constant(-0.75) + Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d far =
      (Eigen::Matrix3d() << 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9).finished();
  std::vector<Eigen::Triplet<double>> entries;
  const auto add = [&](int I, int J, const Eigen::Matrix3d& block) {  // I <= J
    for (int j = 0; j < d; ++j)
      for (int i = 0; i < d; ++i)
        if (I < J || i <= j) entries.emplace_back(I * d + i, J * d + j, block(i, j));
  };
  for (int J = 0; J < nodes; ++J) {
    add(J, J, diagonal);
    if (J >= 1) add(J - 1, J, near);
    if (J >= 7) add(J - 7, J, far);
  }
  Eigen::SparseMatrix<double> upper(nodes * d, nodes * d);
  upper.setFromTriplets(entries.begin(), entries.end());
  std::vector<bool> fixed(static_cast<size_t>(upper.rows()), false);
  for (size_t k = 0; k < fixed.size(); k += 50) fixed[k] = true;
  const SymmetricBlockMatrix matrix(upper, d, fixed);
  EXPECT_EQ(matrix.stored_blocks(), 3 * nodes - 1 - 7);
  EXPECT_LT(matrix.distinct_blocks() * 8, matrix.stored_blocks());
  const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(upper.rows(), -1.0, 2.0);
  Eigen::VectorXd masked = x;
  for (size_t k = 0; k < fixed.size(); ++k)
    if (fixed[k]) masked[static_cast<Eigen::Index>(k)] = 0;
  Eigen::VectorXd expected = upper.selfadjointView<Eigen::Upper>() * masked;
  for (size_t k = 0; k < fixed.size(); ++k)
    if (fixed[k]) expected[static_cast<Eigen::Index>(k)] = x[static_cast<Eigen::Index>(k)];
  for (int threads : {1, 2, 3}) {
    const ThreadScope scope(threads);
    Eigen::VectorXd y;
    matrix.multiply(x, y);
    EXPECT_LT((y - expected).norm(), 1e-13 * expected.norm()) << threads;
  }
  EXPECT_EQ(matrix.diagonal_block(5), diagonal);
  Eigen::Matrix3d with_fixed = diagonal;  // node 50 / 3 = 16 holds the fixed DOF 50 (its 2nd)
  with_fixed.row(2).setZero();
  with_fixed.col(2).setZero();
  with_fixed(2, 2) = 1.0;
  EXPECT_EQ(matrix.diagonal_block(16), with_fixed);

  const SymmetricBlockMatrix random(random_sparse_upper(4000, 3, 7, 3u), 3);
  EXPECT_EQ(random.distinct_blocks(), random.stored_blocks());
}

// Small matrices take the one-thread path.
TEST(BlockCg, SmallProductMatchesDense) {
  const Eigen::MatrixXd dense = random_spd(40, 3, 5u);
  std::vector<bool> fixed(static_cast<size_t>(dense.rows()), false);
  fixed[4] = true;
  const SymmetricBlockMatrix matrix(upper_of(dense), 3, fixed);
  const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(dense.rows(), -1.0, 2.0);
  Eigen::VectorXd y;
  matrix.multiply(x, y);
  const Eigen::VectorXd expected = with_fixed(dense, fixed) * x;
  EXPECT_LT((y - expected).norm(), 1e-12 * expected.norm());
}

TEST(BlockCg, BothPreconditionersSolveToTheTolerance) {
  const Eigen::MatrixXd dense = random_spd(60, 3, 11u);
  std::vector<bool> fixed(static_cast<size_t>(dense.rows()), false);
  for (int k = 0; k < 6; ++k) fixed[static_cast<size_t>(k)] = true;  // two clamped nodes
  fixed[100] = true;                                                 // and one component
  const SymmetricBlockMatrix matrix(upper_of(dense), 3, fixed);
  Eigen::VectorXd rhs = Eigen::VectorXd::Ones(dense.rows());
  for (size_t k = 0; k < fixed.size(); ++k)
    if (fixed[k]) rhs[static_cast<Eigen::Index>(k)] = 0;
  const Eigen::VectorXd exact = with_fixed(dense, fixed).ldlt().solve(rhs);
  for (auto preconditioner :
       {BlockCgOptions::Preconditioner::kJacobi, BlockCgOptions::Preconditioner::kBlockJacobi}) {
    BlockCgOptions options;
    options.preconditioner = preconditioner;
    options.tolerance = 1e-12;
    Eigen::VectorXd solution;
    const BlockCgResult result = block_cg(matrix, rhs, solution, options);
    EXPECT_TRUE(result.converged);
    EXPECT_GT(result.iterations, 1);
    EXPECT_LT(result.relative_residual, 1e-12);
    EXPECT_LT((solution - exact).norm(), 1e-10 * exact.norm());
    EXPECT_EQ(solution[100], 0.0);
  }
}

TEST(BlockCg, ReportsNonConvergenceWithinTheIterationLimit) {
  const Eigen::MatrixXd dense = random_spd(60, 3, 13u);
  const SymmetricBlockMatrix matrix(upper_of(dense), 3);
  BlockCgOptions options;
  options.max_iterations = 2;
  options.tolerance = 1e-14;
  Eigen::VectorXd solution;
  const BlockCgResult result =
      block_cg(matrix, Eigen::VectorXd::LinSpaced(dense.rows(), 1.0, 3.0), solution, options);
  EXPECT_FALSE(result.converged);
  EXPECT_EQ(result.iterations, 2);
  EXPECT_GT(result.relative_residual, 1e-14);
}

TEST(BlockCg, RejectsASizeThatIsNotAMultipleOfTheBlock) {
  const Eigen::MatrixXd dense = random_spd(5, 1, 3u);
  EXPECT_THROW(SymmetricBlockMatrix(upper_of(dense), 3), std::invalid_argument);
}

}  // namespace
}  // namespace isospring::analysis
