// In-place assembly of the immersed bulk stiffness (immersed_pattern.hpp).
#include "immersed_pattern.hpp"

#include <algorithm>

namespace isospring::analysis::detail {

std::vector<std::vector<long>> cell_colours(const ImmersedContext& context) {
  const auto& basis = context.basis;
  int classes = 1;
  for (int d = 0; d < basis.dim(); ++d) classes *= basis.degree(d) + 1;
  std::vector<std::vector<long>> colours(static_cast<size_t>(classes));
  for (size_t c = 0; c < context.cell_elements.size(); ++c) {
    const Element& e = context.cell_elements[c];
    int colour = 0;
    for (int d = basis.dim() - 1; d >= 0; --d)
      colour = colour * (basis.degree(d) + 1) + e[static_cast<size_t>(d)] % (basis.degree(d) + 1);
    colours[static_cast<size_t>(colour)].push_back(static_cast<long>(c));
  }
  return colours;
}

ImmersedPattern::ImmersedPattern(const ImmersedContext& context,
                                 const std::vector<int>& node_of_control_point, int nodes, int dim)
    : dim_(dim) {
  const auto& basis = context.basis;
  const size_t cells = context.cell_elements.size();
  cell_nodes_.resize(cells);
  std::vector<int> cps;
  std::vector<std::vector<int>> rows(static_cast<size_t>(nodes));
  colours_ = cell_colours(context);
  for (size_t c = 0; c < cells; ++c) {
    const Element& e = context.cell_elements[c];
    basis.control_points(e, cps);
    auto& mine = cell_nodes_[c];
    for (int cp : cps) mine.push_back(node_of_control_point[static_cast<size_t>(cp)]);
    for (int b : mine)
      for (int a : mine)
        if (a <= b) rows[static_cast<size_t>(b)].push_back(a);
  }
  offset_.assign(static_cast<size_t>(nodes) + 1, 0);
  for (size_t b = 0; b < rows.size(); ++b) {
    std::sort(rows[b].begin(), rows[b].end());
    rows[b].erase(std::unique(rows[b].begin(), rows[b].end()), rows[b].end());
    offset_[b + 1] = offset_[b] + static_cast<int>(rows[b].size());
  }
  nodes_.reserve(static_cast<size_t>(offset_.back()));
  for (auto& row : rows) {
    nodes_.insert(nodes_.end(), row.begin(), row.end());
    std::vector<int>().swap(row);
  }
}

// Column (B, j) holds the rows A * dim + i of every A in B's row, except (B, i > j): the strict
// upper triangle of the node blocks plus the upper triangle of the diagonal block.
Eigen::SparseMatrix<double> ImmersedPattern::empty_matrix() const {
  const int nodes = static_cast<int>(offset_.size()) - 1;
  const Eigen::Index dofs = static_cast<Eigen::Index>(nodes) * dim_;
  Eigen::SparseMatrix<double> m(dofs, dofs);
  Eigen::VectorXi per_column(dofs);
  for (int b = 0; b < nodes; ++b)
    for (int j = 0; j < dim_; ++j)
      per_column[b * dim_ + j] =
          (offset_[static_cast<size_t>(b) + 1] - offset_[static_cast<size_t>(b)] - 1) * dim_ + j +
          1;
  m.reserve(per_column);
  for (int b = 0; b < nodes; ++b)
    for (int j = 0; j < dim_; ++j)
      for (int k = offset_[static_cast<size_t>(b)]; k < offset_[static_cast<size_t>(b) + 1]; ++k) {
        const int a = nodes_[static_cast<size_t>(k)];
        for (int i = 0; i < dim_ && (a < b || i <= j); ++i)
          m.insert(a * dim_ + i, b * dim_ + j) = 0.0;
      }
  m.makeCompressed();
  return m;
}

void ImmersedPattern::add(size_t cell, const Eigen::MatrixXd& local,
                          Eigen::SparseMatrix<double>& matrix) const {
  const std::vector<int>& nodes = cell_nodes_[cell];
  const int* outer = matrix.outerIndexPtr();
  double* values = matrix.valuePtr();
  for (size_t b = 0; b < nodes.size(); ++b) {
    const int B = nodes[b];
    const int* row = nodes_.data() + offset_[static_cast<size_t>(B)];
    const int* end = nodes_.data() + offset_[static_cast<size_t>(B) + 1];
    for (size_t a = 0; a < nodes.size(); ++a) {
      const int A = nodes[a];
      if (A > B) continue;
      // A's place in B's row; its entries in column (B, j) start at outer + place * dim.
      const int place = static_cast<int>(std::lower_bound(row, end, A) - row);
      for (int j = 0; j < dim_; ++j) {
        double* column = values + outer[B * dim_ + j] + place * dim_;
        for (int i = 0; i < dim_ && (A < B || i <= j); ++i)
          column[i] += local(static_cast<Eigen::Index>(a) * dim_ + i,
                             static_cast<Eigen::Index>(b) * dim_ + j);
      }
    }
  }
}

}  // namespace isospring::analysis::detail
