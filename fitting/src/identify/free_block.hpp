#pragma once
// The free-free block of a symmetric matrix, as the upper triangle that CHOLMOD reads: shared by
// the identification's linear and nonlinear forward models.
#include <Eigen/SparseCore>
#include <algorithm>
#include <vector>

namespace isospring::fitting::detail {

/// Upper triangle of m restricted to the DOFs with free_index >= 0 (renumbered by free_index,
/// which keeps the order of the DOFs). Built column by column: m's columns are sorted, so the
/// block's are too (the same matrix as from triplets, without their sort; that sort took seconds
/// per term at 11,025 DOFs of degree 3, for every model of the identification loop).
inline Eigen::SparseMatrix<double> free_upper_block(const Eigen::SparseMatrix<double>& m,
                                                    const std::vector<int>& free_index,
                                                    int num_free) {
  Eigen::SparseMatrix<double> block(num_free, num_free);
  bool sorted = m.isCompressed();
  for (int c = 0; c < m.outerSize() && sorted; ++c)
    for (int i = m.outerIndexPtr()[c] + 1; i < m.outerIndexPtr()[c + 1] && sorted; ++i)
      sorted = m.innerIndexPtr()[i - 1] < m.innerIndexPtr()[i];
  if (!sorted) {  // e.g. a full matrix made from an upper triangle: through triplets
    std::vector<Eigen::Triplet<double>> triplets;
    for (int c = 0; c < m.outerSize(); ++c)
      for (Eigen::SparseMatrix<double>::InnerIterator it(m, c); it; ++it) {
        const int fr = free_index[static_cast<size_t>(it.row())];
        const int fc = free_index[static_cast<size_t>(it.col())];
        if (fr >= 0 && fc >= 0 && fr <= fc) triplets.emplace_back(fr, fc, it.value());
      }
    block.setFromTriplets(triplets.begin(), triplets.end());
    return block;
  }
  // Free columns in order (free_index increases with the DOF); within a column, the free rows
  // up to the diagonal in m's (sorted) order.
  std::vector<int> outer(static_cast<size_t>(num_free) + 1, 0), inner;
  std::vector<double> values;
  for (int c = 0; c < m.outerSize(); ++c) {
    const int fc = free_index[static_cast<size_t>(c)];
    if (fc < 0) continue;
    for (int i = m.outerIndexPtr()[c]; i < m.outerIndexPtr()[c + 1]; ++i) {
      const int fr = free_index[static_cast<size_t>(m.innerIndexPtr()[i])];
      if (fr >= 0 && fr <= fc) {
        inner.push_back(fr);
        values.push_back(m.valuePtr()[i]);
      }
    }
    outer[static_cast<size_t>(fc) + 1] = static_cast<int>(inner.size());
  }
  for (size_t c = 1; c < outer.size(); ++c) outer[c] = std::max(outer[c], outer[c - 1]);
  block.resizeNonZeros(static_cast<Eigen::Index>(inner.size()));
  std::copy(outer.begin(), outer.end(), block.outerIndexPtr());
  std::copy(inner.begin(), inner.end(), block.innerIndexPtr());
  std::copy(values.begin(), values.end(), block.valuePtr());
  return block;
}

}  // namespace isospring::fitting::detail
