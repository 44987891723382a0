#pragma once
// The free-free block of a symmetric matrix, as the upper triangle that CHOLMOD reads: shared by
// the identification's linear and nonlinear forward models.
#include <Eigen/SparseCore>
#include <vector>

namespace isospring::fitting::detail {

/// Upper triangle of m restricted to the DOFs with free_index >= 0 (renumbered by free_index).
inline Eigen::SparseMatrix<double> free_upper_block(const Eigen::SparseMatrix<double>& m,
                                                    const std::vector<int>& free_index,
                                                    int num_free) {
  std::vector<Eigen::Triplet<double>> triplets;
  for (int c = 0; c < m.outerSize(); ++c)
    for (Eigen::SparseMatrix<double>::InnerIterator it(m, c); it; ++it) {
      const int fr = free_index[static_cast<size_t>(it.row())];
      const int fc = free_index[static_cast<size_t>(it.col())];
      if (fr >= 0 && fc >= 0 && fr <= fc) triplets.emplace_back(fr, fc, it.value());
    }
  Eigen::SparseMatrix<double> block(num_free, num_free);
  block.setFromTriplets(triplets.begin(), triplets.end());
  return block;
}

}  // namespace isospring::fitting::detail
