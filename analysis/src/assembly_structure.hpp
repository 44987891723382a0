#pragma once
// Element list, element colouring and the node-level sparsity of a problem: built once and shared
// by the stiffness and mass assemblies.
#include <Eigen/Sparse>
#include <functional>
#include <vector>

#include "isospring/analysis/dof_map.hpp"
#include "patch_quadrature.hpp"

namespace isospring::analysis::detail {

struct AssemblyStructure {
  /// with_pattern = false builds the element list only (no colours, no pattern): the distributed
  /// backend assembles its own elements into PETSc, and the pattern of every node of a 10^6-DOF
  /// model would cost each MPI rank ~100 MB it never uses.
  AssemblyStructure(const Problem& problem, const DofMap& dofs, bool with_pattern = true);

  std::vector<PatchQuadrature> quadratures;  // one volume rule per patch
  struct Element {
    int patch;
    int index;  // within the patch
  };
  std::vector<Element> elements;
  std::vector<int> node_offset;  // element e's nodes: nodes[node_offset[e] .. node_offset[e+1])
  std::vector<int> nodes;
  std::vector<std::vector<int>> colours;  // element indices per colour
  // Upper node pattern: for node B the nodes A <= B coupled to it, sorted (B last).
  std::vector<int> pattern_offset;
  std::vector<int> pattern;
  int dofs_per_node = 3;
  int num_nodes = 0;

  /// An empty upper-triangular DOF matrix with the structure's pattern.
  Eigen::SparseMatrix<double> empty_matrix() const;
  /// Adds the local matrix (local DOF a * dofs_per_node + i) of element e into `matrix`
  /// (from empty_matrix()); only entries with global row <= column are used.
  void scatter(int element, const Eigen::MatrixXd& local,
               Eigen::SparseMatrix<double>& matrix) const;
};

/// Runs `element_matrix(e, point_buffer, local)` for every element, colour by colour in parallel,
/// and scatters the results. The callback may throw nurbs::InputError; the first one is rethrown.
Eigen::SparseMatrix<double> assemble_matrix(
    const AssemblyStructure& structure,
    const std::function<void(int element, QuadraturePoint& point, Eigen::MatrixXd& local)>&
        element_matrix);

/// The stiffness matrix of linear elasticity of one element (local DOF a * dim + i, symmetric,
/// both triangles filled): the kernel of assemble_stiffness and of the PETSc backend.
class ElementStiffness {
 public:
  ElementStiffness(const Problem& problem, const AssemblyStructure& structure);
  void operator()(int element, QuadraturePoint& point, Eigen::MatrixXd& local) const;

 private:
  const AssemblyStructure* structure_;
  int dim_;
  double lambda_, mu_, thickness_;
};

/// Physical dimension of the formulation, Jacobian determinant check and gradients: fills
/// `gradients` (n x dim) = dR/dx and returns det J. Throws InputError when det J <= 0.
double physical_gradients(const QuadraturePoint& point, int dim, int patch, int element,
                          Eigen::MatrixXd& gradients);

}  // namespace isospring::analysis::detail
