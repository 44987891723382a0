// Element colouring, node sparsity pattern and the parallel element loop.
#include "assembly_structure.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <sstream>
#include <utility>

#include "isospring/nurbs/error.hpp"

namespace isospring::analysis::detail {

AssemblyStructure::AssemblyStructure(const Problem& problem, const DofMap& dofs, bool with_pattern)
    : dofs_per_node(dofs.dofs_per_node()), num_nodes(dofs.num_nodes()) {
  quadratures.reserve(problem.patches.size());
  node_offset.push_back(0);
  std::vector<int> local;
  for (size_t p = 0; p < problem.patches.size(); ++p) {
    quadratures.push_back(PatchQuadrature::volume(problem.patches[p], problem.quadrature_points));
    const auto& quadrature = quadratures.back();
    local.resize(static_cast<size_t>(quadrature.basis_count()));
    for (int e = 0; e < quadrature.num_elements(); ++e) {
      elements.push_back({static_cast<int>(p), e});
      quadrature.element_control_points(e, local.data());
      for (int cp : local) nodes.push_back(dofs.node(static_cast<int>(p), cp));
      node_offset.push_back(static_cast<int>(nodes.size()));
    }
  }
  if (!with_pattern) return;
  const int num_elements = static_cast<int>(elements.size());

  // Node -> elements.
  std::vector<int> touch_offset(static_cast<size_t>(num_nodes) + 1, 0);
  for (int n : nodes) ++touch_offset[static_cast<size_t>(n) + 1];
  for (int n = 0; n < num_nodes; ++n)
    touch_offset[static_cast<size_t>(n) + 1] += touch_offset[static_cast<size_t>(n)];
  std::vector<int> touch(nodes.size());
  {
    std::vector<int> fill(touch_offset.begin(), touch_offset.end() - 1);
    for (int e = 0; e < num_elements; ++e)
      for (int k = node_offset[static_cast<size_t>(e)]; k < node_offset[static_cast<size_t>(e) + 1];
           ++k)
        touch[static_cast<size_t>(fill[static_cast<size_t>(nodes[static_cast<size_t>(k)])]++)] = e;
  }

  // Greedy colouring: an element takes the smallest colour none of its node-sharing neighbours has.
  std::vector<int> colour(static_cast<size_t>(num_elements), -1);
  std::vector<int> seen_by;  // seen_by[c] == e: colour c is taken by a neighbour of e
  for (int e = 0; e < num_elements; ++e) {
    for (int k = node_offset[static_cast<size_t>(e)]; k < node_offset[static_cast<size_t>(e) + 1];
         ++k) {
      const int n = nodes[static_cast<size_t>(k)];
      for (int t = touch_offset[static_cast<size_t>(n)];
           t < touch_offset[static_cast<size_t>(n) + 1]; ++t) {
        const int c = colour[static_cast<size_t>(touch[static_cast<size_t>(t)])];
        if (c >= 0) {
          if (static_cast<int>(seen_by.size()) <= c) seen_by.resize(static_cast<size_t>(c) + 1, -1);
          seen_by[static_cast<size_t>(c)] = e;
        }
      }
    }
    int c = 0;
    while (c < static_cast<int>(seen_by.size()) && seen_by[static_cast<size_t>(c)] == e) ++c;
    colour[static_cast<size_t>(e)] = c;
    if (static_cast<int>(colours.size()) <= c) colours.resize(static_cast<size_t>(c) + 1);
    colours[static_cast<size_t>(c)].push_back(e);
  }

  // Upper node pattern: nodes A <= B sharing an element with B.
  std::vector<std::vector<int>> rows(static_cast<size_t>(num_nodes));
#pragma omp parallel if (num_nodes >= 4096)
  {
    std::vector<int> mark(static_cast<size_t>(num_nodes), -1);
#pragma omp for schedule(dynamic, 256)
    for (int b = 0; b < num_nodes; ++b) {
      auto& row = rows[static_cast<size_t>(b)];
      for (int t = touch_offset[static_cast<size_t>(b)];
           t < touch_offset[static_cast<size_t>(b) + 1]; ++t) {
        const int e = touch[static_cast<size_t>(t)];
        for (int k = node_offset[static_cast<size_t>(e)];
             k < node_offset[static_cast<size_t>(e) + 1]; ++k) {
          const int a = nodes[static_cast<size_t>(k)];
          if (a <= b && mark[static_cast<size_t>(a)] != b) {
            mark[static_cast<size_t>(a)] = b;
            row.push_back(a);
          }
        }
      }
      std::sort(row.begin(), row.end());
    }
  }
  pattern_offset.assign(static_cast<size_t>(num_nodes) + 1, 0);
  for (int b = 0; b < num_nodes; ++b)
    pattern_offset[static_cast<size_t>(b) + 1] =
        pattern_offset[static_cast<size_t>(b)] +
        static_cast<int>(rows[static_cast<size_t>(b)].size());
  pattern.reserve(static_cast<size_t>(pattern_offset.back()));
  for (auto& row : rows) {
    pattern.insert(pattern.end(), row.begin(), row.end());
    std::vector<int>().swap(row);
  }
}

Eigen::SparseMatrix<double> AssemblyStructure::empty_matrix() const {
  Eigen::SparseMatrix<double> matrix;
  empty_matrix(matrix);
  return matrix;
}

void AssemblyStructure::empty_matrix(Eigen::SparseMatrix<double>& matrix) const {
  const int d = dofs_per_node;
  const int n = num_nodes * d;
  // Column (B, j) holds rows (A, 0..d-1) for the coupled nodes A < B, then (B, 0..j).
  // resize and resizeNonZeros keep the matrix's allocation when it is large enough.
  matrix.resize(n, n);
  matrix.makeCompressed();
  long long nnz = 0;
  for (int b = 0; b < num_nodes; ++b) {
    const long long coupled =
        pattern_offset[static_cast<size_t>(b) + 1] - pattern_offset[static_cast<size_t>(b)] - 1;
    nnz += d * (coupled * d) + d * (d + 1) / 2;
  }
  matrix.resizeNonZeros(static_cast<Eigen::Index>(nnz));
  int* outer = matrix.outerIndexPtr();
  int* inner = matrix.innerIndexPtr();
  int at = 0;
  for (int b = 0; b < num_nodes; ++b)
    for (int j = 0; j < d; ++j) {
      outer[b * d + j] = at;
      for (int k = pattern_offset[static_cast<size_t>(b)];
           k < pattern_offset[static_cast<size_t>(b) + 1] - 1; ++k)
        for (int i = 0; i < d; ++i) inner[at++] = pattern[static_cast<size_t>(k)] * d + i;
      for (int i = 0; i <= j; ++i) inner[at++] = b * d + i;
    }
  outer[n] = at;
  std::fill(matrix.valuePtr(), matrix.valuePtr() + nnz, 0.0);
}

void AssemblyStructure::scatter(int element, const Eigen::MatrixXd& local,
                                Eigen::SparseMatrix<double>& matrix) const {
  const int d = dofs_per_node;
  const int* element_nodes = nodes.data() + node_offset[static_cast<size_t>(element)];
  const int n =
      node_offset[static_cast<size_t>(element) + 1] - node_offset[static_cast<size_t>(element)];
  const int* outer = matrix.outerIndexPtr();
  double* values = matrix.valuePtr();
  // The element's nodes in ascending global order (with their local index): for each column
  // node B the coupled nodes A <= B then come in the order of B's pattern row, found by one merge
  // instead of a binary search per pair. A node may appear twice (a glued seam).
  thread_local std::vector<std::pair<int, int>> sorted;
  sorted.resize(static_cast<size_t>(n));
  for (int a = 0; a < n; ++a) sorted[static_cast<size_t>(a)] = {element_nodes[a], a};
  std::sort(sorted.begin(), sorted.end());
  for (const auto& [B, b] : sorted) {
    const int* row = pattern.data() + pattern_offset[static_cast<size_t>(B)];
    int k = 0;
    for (const auto& [A, a] : sorted) {
      if (A > B) break;  // the mirror entries (in the lower triangle)
      while (row[k] < A) ++k;
      for (int j = 0; j < d; ++j) {
        double* column = values + outer[B * d + j] + k * d;
        const double* source = local.data() +
                               (static_cast<Eigen::Index>(b) * d + j) * local.rows() +
                               static_cast<Eigen::Index>(a) * d;
        const int rows = A == B ? j + 1 : d;  // the diagonal block's upper triangle only
        for (int i = 0; i < rows; ++i) column[i] += source[i];
      }
    }
  }
}

bool colour_in_parallel(int count, bool heavy_work, int team) {
  return team > 1 && (count >= kLargeColour || (count >= 2 && heavy_work));
}

bool heavy_elements(const AssemblyStructure& structure) {
  constexpr int kHeavyElement = 81;
  for (const auto& quadrature : structure.quadratures)
    if (quadrature.basis_count() * structure.dofs_per_node >= kHeavyElement) return true;
  return false;
}

std::vector<Eigen::SparseMatrix<double>> assemble_matrices(
    const AssemblyStructure& structure, size_t count,
    const std::function<void(int, QuadraturePoint&, std::vector<Eigen::MatrixXd>&)>&
        element_matrices,
    int threads) {
  std::vector<Eigen::SparseMatrix<double>> matrices(count, structure.empty_matrix());
  struct Scratch {
    QuadraturePoint point;
    std::vector<Eigen::MatrixXd> locals;
  };
  for_each_element_by_colour<Scratch>(structure, threads, heavy_elements(structure),
                                      [&](int e, Scratch& scratch) {
                                        scratch.locals.resize(count);
                                        element_matrices(e, scratch.point, scratch.locals);
                                        for (size_t k = 0; k < count; ++k)
                                          structure.scatter(e, scratch.locals[k], matrices[k]);
                                      });
  return matrices;
}

Eigen::SparseMatrix<double> assemble_matrix(
    const AssemblyStructure& structure,
    const std::function<void(int, QuadraturePoint&, Eigen::MatrixXd&)>& element_matrix) {
  return std::move(
      assemble_matrices(structure, 1,
                        [&](int e, QuadraturePoint& point, std::vector<Eigen::MatrixXd>& locals) {
                          element_matrix(e, point, locals[0]);
                        })
          .front());
}

double physical_gradients(const QuadraturePoint& point, int dim, int patch, int element,
                          Eigen::MatrixXd& gradients) {
  double det;
  if (dim == 2) {
    const Eigen::Matrix2d J = point.jacobian.topLeftCorner<2, 2>();
    det = J.determinant();
    if (det > 0.0) gradients.noalias() = point.derivatives * J.inverse();
  } else {
    const Eigen::Matrix3d& J = point.jacobian;
    det = J.determinant();
    if (det > 0.0) gradients.noalias() = point.derivatives * J.inverse();
  }
  if (!(det > 0.0)) {
    std::ostringstream message;
    message << "patch " << patch;
    if (element >= 0) message << ", element " << element;
    message << ": the Jacobian determinant is " << det << " at parameter (" << point.param[0]
            << ", " << point.param[1];
    if (dim == 3) message << ", " << point.param[2];
    message << "); the parametrisation is inverted or degenerate there (fix the control net "
               "ordering/orientation so that det(dX/du) > 0 everywhere, or split the patch)";
    throw nurbs::InputError(message.str());
  }
  return det;
}

}  // namespace isospring::analysis::detail
