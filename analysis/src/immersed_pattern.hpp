#pragma once
// The bulk stiffness of an immersed domain assembled in place: the upper-triangular DOF pattern
// of the active cells (two nodes couple when one cell's basis holds both), built once, and the
// cells added into it colour by colour. Why not triplets: a cell of degree 2 in 3D gives 3,321
// upper entries, so the triplets of a 50,000-DOF grid took ~0.5 GB per copy (each thread's, the
// joined list, the sort), several times the matrix itself.
//
// Colours: cells whose element indices differ by at least p_d + 1 in some direction d share no
// basis function, so the cells of one class of (element index mod p_d + 1) touch disjoint
// columns and are added on all threads without locks; the classes run one after another, so
// each entry's sum has the same order for any thread count.
#include <Eigen/SparseCore>
#include <vector>

#include "immersed_kernels.hpp"

namespace isospring::analysis::detail {

/// The cells of each colour (cell indices, ascending), the classes of (element index mod p_d + 1).
std::vector<std::vector<long>> cell_colours(const ImmersedContext& context);

class ImmersedPattern {
 public:
  /// Cells' nodes (`node_of_control_point` of their control points) from `context`.
  ImmersedPattern(const ImmersedContext& context, const std::vector<int>& node_of_control_point,
                  int nodes, int dim);

  /// An upper-triangular matrix (dofs x dofs) with the pattern and zero values.
  Eigen::SparseMatrix<double> empty_matrix() const;
  /// Adds cell c's local matrix (local DOF a * dim + i, both triangles) into `matrix`'s upper
  /// triangle.
  void add(size_t cell, const Eigen::MatrixXd& local, Eigen::SparseMatrix<double>& matrix) const;
  /// Cells per colour (cell indices, ascending).
  const std::vector<std::vector<long>>& colours() const { return colours_; }

 private:
  int dim_;
  std::vector<std::vector<int>> cell_nodes_;
  std::vector<int> offset_, nodes_;  // node B's upper row: nodes_[offset_[B] .. offset_[B + 1])
  std::vector<std::vector<long>> colours_;
};

}  // namespace isospring::analysis::detail
