// Elimination of prescribed DOFs.
#include "reduced_system.hpp"

namespace isospring::analysis::detail {

ReducedSystem::ReducedSystem(const Eigen::SparseMatrix<double>& matrix,
                             const Constraints& constraints) {
  const int n = static_cast<int>(matrix.rows());
  free_index.assign(static_cast<size_t>(n), 0);
  prescribed = Eigen::VectorXd::Zero(n);
  for (size_t k = 0; k < constraints.dofs.size(); ++k) {
    free_index[static_cast<size_t>(constraints.dofs[k])] = -1;
    prescribed[constraints.dofs[k]] = constraints.values[k];
  }
  for (int d = 0; d < n; ++d)
    if (free_index[static_cast<size_t>(d)] == 0) {
      free_index[static_cast<size_t>(d)] = static_cast<int>(free_dofs.size());
      free_dofs.push_back(d);
    }
  coupling = matrix.selfadjointView<Eigen::Upper>() * prescribed;

  // Columns of free DOFs keep their free rows; the renumbering is monotone, so the upper
  // triangle stays upper and rows stay sorted.
  const int m = static_cast<int>(free_dofs.size());
  Eigen::SparseMatrix<double> reduced(m, m);
  Eigen::Index nnz = 0;
  for (int c : free_dofs)
    for (Eigen::SparseMatrix<double>::InnerIterator it(matrix, c); it; ++it)
      if (free_index[static_cast<size_t>(it.row())] >= 0) ++nnz;
  reduced.resizeNonZeros(nnz);
  Eigen::Index at = 0;
  for (int j = 0; j < m; ++j) {
    reduced.outerIndexPtr()[j] = static_cast<int>(at);
    for (Eigen::SparseMatrix<double>::InnerIterator it(matrix, free_dofs[static_cast<size_t>(j)]);
         it; ++it) {
      const int row = free_index[static_cast<size_t>(it.row())];
      if (row < 0) continue;
      reduced.innerIndexPtr()[at] = row;
      reduced.valuePtr()[at] = it.value();
      ++at;
    }
  }
  reduced.outerIndexPtr()[m] = static_cast<int>(at);
  free_matrix = std::move(reduced);
}

Eigen::VectorXd ReducedSystem::free_rhs(const Eigen::VectorXd& force) const {
  Eigen::VectorXd rhs(static_cast<Eigen::Index>(free_dofs.size()));
  for (size_t j = 0; j < free_dofs.size(); ++j)
    rhs[static_cast<Eigen::Index>(j)] = force[free_dofs[j]] - coupling[free_dofs[j]];
  return rhs;
}

Eigen::VectorXd ReducedSystem::expand(const Eigen::VectorXd& free_solution) const {
  Eigen::VectorXd u = prescribed;
  for (size_t j = 0; j < free_dofs.size(); ++j)
    u[free_dofs[j]] = free_solution[static_cast<Eigen::Index>(j)];
  return u;
}

}  // namespace isospring::analysis::detail
