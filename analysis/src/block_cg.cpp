// Node-block symmetric storage, its threaded product and preconditioned conjugate gradients.
#include "isospring/analysis/block_cg.hpp"

#include <omp.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <type_traits>
#include <unordered_map>

namespace isospring::analysis {

SymmetricBlockMatrix::SymmetricBlockMatrix(const Eigen::SparseMatrix<double>& upper, int block_size,
                                           const std::vector<bool>& fixed)
    : rows_(upper.rows()), block_size_(block_size) {
  const int d = block_size;
  if (d < 1 || upper.rows() != upper.cols() || upper.rows() % d != 0)
    throw std::invalid_argument("SymmetricBlockMatrix: the size is not a multiple of the block");
  const auto is_fixed = [&](Eigen::Index k) {
    return !fixed.empty() && fixed[static_cast<size_t>(k)];
  };
  const Eigen::Index blocks = rows_ / d;
  column_start_.assign(static_cast<size_t>(blocks) + 1, 0);
  block_row_.reserve(static_cast<size_t>(upper.nonZeros() / (d * d) + blocks));
  values_.reserve(block_row_.capacity() * static_cast<size_t>(d * d));
  // slot[I]: where block row I of the current block column is, valid when seen[I] == J.
  std::vector<Eigen::Index> slot(static_cast<size_t>(blocks), 0),
      seen(static_cast<size_t>(blocks), -1);
  for (Eigen::Index J = 0; J < blocks; ++J) {
    column_start_[static_cast<size_t>(J)] = static_cast<Eigen::Index>(block_row_.size());
    const auto block_of = [&](Eigen::Index I) {
      if (seen[static_cast<size_t>(I)] != J) {
        seen[static_cast<size_t>(I)] = J;
        slot[static_cast<size_t>(I)] = static_cast<Eigen::Index>(block_row_.size());
        block_row_.push_back(static_cast<int>(I));
        values_.resize(values_.size() + static_cast<size_t>(d * d), 0.0);
      }
      return values_.data() + slot[static_cast<size_t>(I)] * d * d;
    };
    // The diagonal block first, so that the product finds it without a search.
    block_of(J);
    for (int k = 0; k < d; ++k) {
      const Eigen::Index c = J * d + k;
      if (is_fixed(c)) continue;
      for (Eigen::SparseMatrix<double>::InnerIterator it(upper, c); it; ++it) {
        if (it.row() > c || is_fixed(it.row())) continue;
        block_of(it.row() / d)[k * d + it.row() % d] = it.value();
      }
    }
    // Complete the diagonal block's lower triangle; fixed DOFs get their unit diagonal.
    double* diagonal = values_.data() + column_start_[static_cast<size_t>(J)] * d * d;
    for (int k = 0; k < d; ++k) {
      if (is_fixed(J * d + k)) diagonal[k * d + k] = 1.0;
      for (int i = k + 1; i < d; ++i) diagonal[k * d + i] = diagonal[i * d + k];
    }
  }
  column_start_.back() = static_cast<Eigen::Index>(block_row_.size());
  share_repeated_blocks();
}

namespace {

// A block's values as a hash key, compared bit by bit (so -0.0 and 0.0 differ, and a NaN
// equals itself): blocks that compare equal give the same products.
struct BlockKey {
  const double* values;
  int size;
  bool operator==(const BlockKey& other) const {
    return std::memcmp(values, other.values, sizeof(double) * static_cast<size_t>(size)) == 0;
  }
};
struct BlockKeyHash {
  size_t operator()(const BlockKey& key) const {
    uint64_t hash = 1469598103934665603ull;
    for (int k = 0; k < key.size; ++k) {
      uint64_t bits;
      std::memcpy(&bits, key.values + k, sizeof bits);
      hash = (hash ^ bits) * 1099511628211ull;
      hash ^= hash >> 29;
    }
    return static_cast<size_t>(hash);
  }
};

}  // namespace

void SymmetricBlockMatrix::share_repeated_blocks() {
  const int d2 = block_size_ * block_size_;
  const size_t stored = block_row_.size();
  // Small matrices are cheap to multiply either way; the table must stay far smaller than the
  // values to pay for the indirection.
  constexpr size_t kMinimumBlocks = 4096;
  constexpr size_t kDistinctFraction = 8;
  if (stored < kMinimumBlocks) return;
  std::unordered_map<BlockKey, int, BlockKeyHash> index;
  index.reserve(stored / kDistinctFraction + 1);
  std::vector<int> block_value(stored);
  for (size_t b = 0; b < stored; ++b) {
    const auto found = index.try_emplace(BlockKey{values_.data() + b * static_cast<size_t>(d2), d2},
                                         static_cast<int>(index.size()));
    block_value[b] = found.first->second;
    if (index.size() * kDistinctFraction > stored) return;  // too many distinct blocks
  }
  std::vector<double> table(index.size() * static_cast<size_t>(d2));
  for (const auto& [key, id] : index)
    std::copy(key.values, key.values + d2, table.begin() + static_cast<std::ptrdiff_t>(id) * d2);
  values_.swap(table);
  std::vector<double>().swap(table);
  block_value_.swap(block_value);
}

Eigen::MatrixXd SymmetricBlockMatrix::diagonal_block(Eigen::Index block) const {
  const int d = block_size_;
  return Eigen::Map<const Eigen::MatrixXd>(block_values(column_start_[static_cast<size_t>(block)]),
                                           d, d);
}

template <int D, bool Shared>
void SymmetricBlockMatrix::multiply_fixed(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
  using Block = Eigen::Matrix<double, D, D>;
  using Segment = Eigen::Matrix<double, D, 1>;
  const Eigen::Index blocks = rows_ / D;
  // Small matrices on one thread: a parallel region costs microseconds (more when a thread waits
  // for a core on a loaded machine), more than a product of a few thousand blocks.
  constexpr Eigen::Index kParallelValues = 200000;
  const int threads =
      stored_blocks() * D * D < kParallelValues ? 1 : std::max(1, omp_get_max_threads());
  if (static_cast<int>(scratch_.size()) < threads) scratch_.resize(static_cast<size_t>(threads));
#pragma omp parallel num_threads(threads)
  {
    const int t = omp_get_thread_num(), used = omp_get_num_threads();
    // Contiguous block columns with equal numbers of stored blocks per thread.
    const auto boundary = [&](int k) {
      const Eigen::Index target = column_start_.back() * k / used;
      return static_cast<Eigen::Index>(
          std::lower_bound(column_start_.begin(), column_start_.end(), target) -
          column_start_.begin());
    };
    const Eigen::Index first = std::min(boundary(t), blocks),
                       last = t + 1 == used ? blocks : std::min(boundary(t + 1), blocks);
    Eigen::VectorXd& out = used == 1 ? y : scratch_[static_cast<size_t>(t)];
    out.setZero(rows_);
    for (Eigen::Index J = first; J < last; ++J) {
      const Segment xj = x.template segment<D>(J * D);
      const Eigen::Index begin = column_start_[static_cast<size_t>(J)],
                         end = column_start_[static_cast<size_t>(J) + 1];
      // Diagonal block (stored first): one product.
      const auto values = [&](Eigen::Index b) {
        return values_.data() +
               (Shared ? static_cast<Eigen::Index>(block_value_[static_cast<size_t>(b)]) : b) * D *
                   D;
      };
      Segment yj = Eigen::Map<const Block>(values(begin)) * xj;
      for (Eigen::Index b = begin + 1; b < end; ++b) {
        const Eigen::Map<const Block> a(values(b));
        const Eigen::Index i = block_row_[static_cast<size_t>(b)];
        out.template segment<D>(i * D).noalias() += a * xj;
        yj.noalias() += a.transpose() * x.template segment<D>(i * D);
      }
      out.template segment<D>(J * D) += yj;
    }
    if (used > 1) {
#pragma omp barrier
      // Sum the per-thread vectors, each thread a contiguous range of rows.
      const Eigen::Index from = rows_ * t / used, to = rows_ * (t + 1) / used;
      y.segment(from, to - from) = scratch_[0].segment(from, to - from);
      for (int s = 1; s < used; ++s)
        y.segment(from, to - from) += scratch_[s].segment(from, to - from);
    }
  }
}

template <int D>
void SymmetricBlockMatrix::multiply_block_size(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
  if (block_value_.empty())
    multiply_fixed<D, false>(x, y);
  else
    multiply_fixed<D, true>(x, y);
}

void SymmetricBlockMatrix::multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
  y.resize(rows_);
  switch (block_size_) {
    case 1:
      multiply_block_size<1>(x, y);
      break;
    case 2:
      multiply_block_size<2>(x, y);
      break;
    case 3:
      multiply_block_size<3>(x, y);
      break;
    default:
      throw std::invalid_argument("SymmetricBlockMatrix: block sizes 1, 2, 3 only");
  }
}

BlockCgResult block_cg(const SymmetricBlockMatrix& matrix, const Eigen::VectorXd& rhs,
                       Eigen::VectorXd& solution, const BlockCgOptions& options) {
  const Eigen::Index n = matrix.rows();
  const int d = matrix.block_size();
  const bool blocks = options.preconditioner == BlockCgOptions::Preconditioner::kBlockJacobi;
  // The preconditioner: inverse of each node's diagonal block (or of each diagonal entry).
  Eigen::MatrixXd inverse(d, n);  // columns J*d .. J*d+d-1: the inverse of block J
  for (Eigen::Index J = 0; J < n / d; ++J) {
    const Eigen::MatrixXd block = matrix.diagonal_block(J);
    if (blocks) {
      const Eigen::LLT<Eigen::MatrixXd> llt(block);
      if (llt.info() != Eigen::Success)
        throw std::runtime_error("block-Jacobi CG: a diagonal block is not positive definite");
      inverse.middleCols(J * d, d) = llt.solve(Eigen::MatrixXd::Identity(d, d));
    } else {
      inverse.middleCols(J * d, d).setZero();
      for (int k = 0; k < d; ++k) {
        if (!(block(k, k) > 0))
          throw std::runtime_error("Jacobi CG: a diagonal entry is not positive");
        inverse(k, J * d + k) = 1.0 / block(k, k);
      }
    }
  }
  // Fixed-size node blocks: a dynamic d x d product per node costs more than the block itself.
  const auto apply_blocks = [&](auto size, const Eigen::VectorXd& r, Eigen::VectorXd& z) {
    constexpr int D = decltype(size)::value;
    for (Eigen::Index J = 0; J < n / D; ++J)
      z.template segment<D>(J * D).noalias() =
          Eigen::Map<const Eigen::Matrix<double, D, D>>(inverse.data() + J * D * D) *
          r.template segment<D>(J * D);
  };
  const auto precondition = [&](const Eigen::VectorXd& r, Eigen::VectorXd& z) {
    z.resize(n);
    if (d == 3)
      apply_blocks(std::integral_constant<int, 3>(), r, z);
    else if (d == 2)
      apply_blocks(std::integral_constant<int, 2>(), r, z);
    else if (d == 1)
      apply_blocks(std::integral_constant<int, 1>(), r, z);
    else
      throw std::invalid_argument("block_cg: block sizes 1, 2, 3 only");
  };

  BlockCgResult result;
  solution = Eigen::VectorXd::Zero(n);
  const double rhs_norm = rhs.norm();
  if (rhs_norm == 0) {
    result.converged = true;
    return result;
  }
  const int max_iterations = options.max_iterations > 0
                                 ? options.max_iterations
                                 : static_cast<int>(std::max<Eigen::Index>(1000, 10 * n));
  const double threshold = options.tolerance * options.tolerance * rhs_norm * rhs_norm;
  Eigen::VectorXd residual = rhs, z, direction, product;
  precondition(residual, z);
  direction = z;
  double rz = residual.dot(z), residual_norm2 = residual.squaredNorm();
  while (result.iterations < max_iterations) {
    if (residual_norm2 < threshold) {
      result.converged = true;
      break;
    }
    matrix.multiply(direction, product);
    const double curvature = direction.dot(product);
    if (!(curvature > 0)) throw std::runtime_error("CG: the matrix is not positive definite");
    const double alpha = rz / curvature;
    solution.noalias() += alpha * direction;
    residual.noalias() -= alpha * product;
    residual_norm2 = residual.squaredNorm();
    ++result.iterations;
    precondition(residual, z);
    const double rz_next = residual.dot(z);
    direction = z + (rz_next / rz) * direction;
    rz = rz_next;
  }
  result.converged = result.converged || residual_norm2 < threshold;
  result.relative_residual = std::sqrt(residual_norm2) / rhs_norm;
  return result;
}

}  // namespace isospring::analysis
