#pragma once
// Shared pieces of the immersed assembly: the strain and traction operators of one cell's basis
// and the scatter of local matrices into the active DOFs.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "immersed_basis.hpp"
#include "immersed_cell_rule.hpp"
#include "isospring/analysis/elasticity.hpp"
#include "isospring/analysis/immersed.hpp"

namespace isospring::analysis::detail {

/// Voigt elasticity matrix (2D: xx, yy, xy; 3D: xx, yy, zz, yz, xz, xy; engineering shears).
Eigen::MatrixXd voigt_elasticity(const LameParameters& lame, int dim);
/// Strain operator B (voigt x count*dim) of the basis gradients (count x dim); DOF a*dim+c.
Eigen::MatrixXd strain_operator(const Eigen::MatrixXd& gradients, int dim);
/// Values operator N (dim x count*dim): u = N q.
Eigen::MatrixXd value_operator(const Eigen::VectorXd& values, int dim);
/// The operator taking a voigt stress to the traction sigma n (dim x voigt).
Eigen::MatrixXd normal_operator(const Eigen::Vector3d& n, int dim);

/// Local matrices and vectors scattered into the active DOFs; only the upper triangle of the
/// matrix is kept (row <= column), as every symmetric matrix of the analysis.
struct ImmersedScatter {
  int dim = 2;
  const std::vector<int>* node_of_control_point = nullptr;
  std::vector<Eigen::Triplet<double>> triplets;
  Eigen::VectorXd force;

  void add_matrix(const std::vector<int>& control_points, const Eigen::MatrixXd& local);
  void add_vector(const std::vector<int>& control_points, const Eigen::VectorXd& local);
};

/// Everything the assembly stages share.
struct ImmersedContext {
  const geometry::ImmersedDomain* domain = nullptr;
  const ImmersedOptions* options = nullptr;
  BackgroundBasis basis;
  LameParameters lame;
  double thickness = 1.0;
  Eigen::MatrixXd elasticity;           // voigt
  std::vector<Element> cell_elements;   // element of each domain cell
  std::vector<int> cell_of_element;     // flat element -> cell index, -1 when inactive
  std::vector<CellRule> cell_rules;     // each cell's reduced rule (immersed_cell_rule.hpp)
  std::set<std::pair<int, int>> ghost;  // ghost-penalty faces (see ghost_faces)
};

/// Nitsche terms of the supports and the loads on faces (immersed_boundary_terms.cpp); returns
/// the largest dimensionless penalty beta_K h / (lambda + 2 mu). Each supported element's
/// beta_K is stored in `penalties` (flat element index -> beta_K). With `loads_only`, only the
/// right-hand side is added, with the beta_K read from `penalties` (the matrix is not touched).
double add_face_terms(const ImmersedContext& context, ImmersedScatter& scatter,
                      std::map<int, double>& penalties, bool loads_only = false);
/// Ghost penalty on the faces of cut cells (immersed_ghost_penalty.cpp); returns the face count.
int add_ghost_penalty(const ImmersedContext& context, ImmersedScatter& scatter);
/// The ghost-penalty faces: (flat index of the lower element, normal direction).
std::set<std::pair<int, int>> ghost_faces(const ImmersedContext& context);
/// One face's penalty matrix over the union of both elements' control points `cps`.
void ghost_face_matrix(const ImmersedContext& context, const std::pair<int, int>& face,
                       std::vector<int>& cps, Eigen::MatrixXd& local);
/// The background element of a cell (the one holding its points' centroid, as the assembly
/// assigns it).
Element element_of_cell(const BackgroundBasis& basis, const std::vector<Eigen::Vector3d>& points);
/// Displacement and gradient at x from the basis of element e (x on its closure)
/// (immersed_solve.cpp).
ImmersedPointValue value_on_element(const BackgroundBasis& basis, const Element& e,
                                    const ImmersedResult& result, const Eigen::Vector3d& x,
                                    BasisAt& at);
/// Bulk stiffness of one domain cell over its element's basis (immersed_assembly.cpp).
void cell_stiffness(const ImmersedContext& context, size_t cell, std::vector<int>& cps,
                    Eigen::MatrixXd& local);

}  // namespace isospring::analysis::detail
