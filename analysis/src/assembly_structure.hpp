#pragma once
// Element list, element colouring and the node-level sparsity of a problem: built once and shared
// by the stiffness and mass assemblies.
#include <omp.h>

#include <Eigen/Sparse>
#include <exception>
#include <functional>
#include <string>
#include <vector>

#include "isospring/analysis/dof_map.hpp"
#include "isospring/nurbs/error.hpp"
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
  /// The same in `matrix`, reusing its storage when it is large enough (a matrix assembled again
  /// at every Newton iteration then touches no fresh memory).
  void empty_matrix(Eigen::SparseMatrix<double>& matrix) const;
  /// Adds the local matrix (local DOF a * dofs_per_node + i) of element e into `matrix`
  /// (from empty_matrix()); only entries with global row <= column are used.
  void scatter(int element, const Eigen::MatrixXd& local,
               Eigen::SparseMatrix<double>& matrix) const;
};

/// Whether a colour of `count` elements runs on a team of `team` threads. Small colours run
/// serially: waking threads costs more than it saves, and much more on a loaded machine where
/// OpenMP's spinning threads compete for cores. Except colours of heavy work (element matrices
/// of 81 DOFs and more: degree 2 solids and up, ~3 Mflop each at degree 3), of which a coarse
/// degree-3 net has a few per colour (~64 colours): BM_StiffnessAssembly, 192 degree-3 elements,
/// 99 ms on one thread, 72 ms on two (one element per thread at a time in small colours).
bool colour_in_parallel(int count, bool heavy_work, int team);
/// Colours of at least this many elements run in parallel whatever their work, in chunks of 16
/// elements per thread (smaller ones one element at a time).
constexpr int kLargeColour = 64;
/// Elements whose matrices are heavy work for colour_in_parallel.
bool heavy_elements(const AssemblyStructure& structure);

/// Runs `body(e, scratch)` for every element, colour by colour, on `threads` threads (0: OpenMP's
/// default), with one default-constructed `Scratch` per thread. Elements of one colour share no
/// node, so their scatters never race, and every entry's sum runs colour by colour whatever the
/// thread count. Colours go parallel by colour_in_parallel's rule (`heavy`: heavy_elements, when
/// the body forms element matrices). An exception in `body` does not leave its thread: the first
/// message of a colour is thrown as nurbs::InputError once the colour is done.
template <class Scratch, class Body>
void for_each_element_by_colour(const AssemblyStructure& structure, int threads, bool heavy,
                                Body&& body) {
  std::string error;
  const int team = threads > 0 ? threads : omp_get_max_threads();
  for (const auto& colour : structure.colours) {
    const int count = static_cast<int>(colour.size());
    const int chunk = count >= kLargeColour ? 16 : 1;
#pragma omp parallel num_threads(team) if (colour_in_parallel(count, heavy, team))
    {
      Scratch scratch;
#pragma omp for schedule(dynamic, chunk)
      for (int c = 0; c < count; ++c) {
        try {
          body(colour[static_cast<size_t>(c)], scratch);
        } catch (const std::exception& ex) {
#pragma omp critical(isospring_colour_loop_error)
          if (error.empty()) error = ex.what();
        }
      }
    }
    if (!error.empty()) throw nurbs::InputError(error);
  }
}

/// Runs `element_matrices(e, point_buffer, locals)` (locals: `count` matrices) for every element,
/// colour by colour on `threads` threads (0: OpenMP's default), and scatters local k into
/// matrix k. The callback may throw nurbs::InputError; the first one is rethrown.
std::vector<Eigen::SparseMatrix<double>> assemble_matrices(
    const AssemblyStructure& structure, size_t count,
    const std::function<void(int element, QuadraturePoint& point,
                             std::vector<Eigen::MatrixXd>& locals)>& element_matrices,
    int threads = 0);

/// assemble_matrices for one matrix.
Eigen::SparseMatrix<double> assemble_matrix(
    const AssemblyStructure& structure,
    const std::function<void(int element, QuadraturePoint& point, Eigen::MatrixXd& local)>&
        element_matrix);

/// The stiffness matrix of linear elasticity of one element (local DOF a * dim + i, symmetric,
/// both triangles filled): the kernel of assemble_stiffness and of the PETSc backend. On affine
/// patches (element_classes.hpp) each class of equal elements is integrated once, at
/// construction, and its matrix copied for the others.
class ElementStiffness {
 public:
  /// reuse_equal_elements = false integrates every element (the reference of the tests).
  ElementStiffness(const Problem& problem, const AssemblyStructure& structure,
                   bool reuse_equal_elements = true);
  void operator()(int element, QuadraturePoint& point, Eigen::MatrixXd& local) const;
  /// Elements whose matrix comes from the cache of their class (for tests and reports).
  long long cached_elements() const { return cached_elements_; }

 private:
  void integrate(int element, QuadraturePoint& point, Eigen::MatrixXd& local) const;

  const AssemblyStructure* structure_;
  int dim_;
  double lambda_, mu_, thickness_;
  // Per patch: the class of each element (empty: none cached) and each class's matrix.
  std::vector<std::vector<int>> element_class_;
  std::vector<std::vector<Eigen::MatrixXd>> class_matrix_;
  long long cached_elements_ = 0;
};

/// Physical dimension of the formulation, Jacobian determinant check and gradients: fills
/// `gradients` (n x dim) = dR/dx and returns det J. Throws InputError when det J <= 0.
double physical_gradients(const QuadraturePoint& point, int dim, int patch, int element,
                          Eigen::MatrixXd& gradients);

}  // namespace isospring::analysis::detail
