#pragma once
// B-bar for NURBS: the volumetric strain projected onto splines of one degree lower.
//
// Why this formulation. At low degree and nu -> 0.5 the displacement formulation locks: every
// quadrature point constrains div u, far more constraints than displacement DOFs. B-bar (Elguedj,
// Bazilevs, Calo, Hughes, CMAME 197 (2008) 2732-2762) replaces div u by its projection onto the
// space Q of splines of degree p - 1 on the same knots (continuity one lower): about one
// constraint per element in any dimension, the ratio of the stable NURBS Q_p/Q_{p-1} pair, whose
// pressure converges at O(h^p) so displacements keep their optimal rates. The exact L2
// projection onto Q needs the inverse of Q's Gram matrix, which makes the stiffness dense per
// patch. The local projection used here instead projects element by element onto the
// functions of Q that live on the element and averages each coefficient over the elements of
// its support, weighted by the function's integral over each (a local least-squares
// quasi-interpolant in the sense of Govindjee, Strain, Mitchell and Taylor, CMAME 2012). It
// reproduces Q exactly (so constants and the patch test are kept), preserves integrals,
// converges at the same rate (tests: Lame at nu = 0.4999), and couples control points up to
// 3p - 2 apart per direction (p for the displacement formulation): a sparse stiffness, wider
// than the displacement one (see docs/limitations.md). A mixed
// displacement-pressure form would keep the pattern but turn the SPD system into a saddle point
// that the direct and CG solvers (and the cached factorisations of identify) cannot use.
//
// The energy is split as mu |dev eps|^2 + kappa / 2 (Pi div u)^2 with the 3D deviator (plane
// strain: eps_zz = 0) and kappa = lambda + 2 mu / 3: the element kernel runs with lambda
// replaced by -2 mu / 3 (its mu |eps|^2 + lambda' / 2 (div u)^2 is then the deviatoric part)
// and the volumetric matrix kappa C^T G C is added, C the projection operator and G Q's Gram.
#include <Eigen/Sparse>
#include <array>
#include <functional>
#include <vector>

#include "assembly_structure.hpp"
#include "isospring/analysis/elasticity.hpp"
#include "isospring/analysis/problem.hpp"

namespace isospring::analysis::detail {

/// The projection space Q of one patch: tensor-product B-splines of degree p_d - 1 per direction
/// on the patch's knots (interior multiplicities capped at the lower degree, i.e. C^0 where the
/// displacement is C^0); degree 0 is one constant per element. Polynomial in the parameters
/// (not rational): the projection needs the space, not the geometry.
class PressureSpace {
 public:
  explicit PressureSpace(const nurbs::Patch& patch);
  int size() const { return size_; }
  /// Functions non-zero on one element.
  int local_count() const { return local_count_; }
  /// Per-direction element indices of parameter u (the last element at the upper end).
  std::array<int, 3> element_of(const nurbs::Param& u) const;
  /// Indices (within the patch's space) and values of the local functions of `element` at u.
  void evaluate(const std::array<int, 3>& element, const nurbs::Param& u, int* indices,
                double* values) const;

 private:
  struct Direction {
    int degree = 0;             // of Q
    nurbs::KnotVector reduced;  // degree >= 1 only
    std::vector<int> first;     // per element: first function index
    nurbs::KnotVector displacement;
    std::vector<int> element_spans;
    int count = 1;
  };
  std::array<Direction, 3> directions_;
  int param_dim_ = 0;
  int size_ = 0;
  int local_count_ = 1;
};

/// The projection as matrices over a column numbering of the displacement components:
/// coefficients of Pi div u in Q (all patches stacked) = operator * u; gram = int N_A N_B dV
/// (without the 2D thickness).
struct VolumetricProjection {
  std::vector<PressureSpace> spaces;
  std::vector<int> offset;  // first row of each patch
  Eigen::SparseMatrix<double, Eigen::RowMajor> projection;
  Eigen::SparseMatrix<double> gram;
};
/// `column(patch, control_point, component)` numbers the displacement components (columns
/// columns); `quadratures` one volume rule per patch (the solve's).
VolumetricProjection volumetric_projection(
    const Problem& problem, const std::vector<PatchQuadrature>& quadratures, int columns,
    const std::function<int(int patch, int control_point, int component)>& column);

/// Throws nurbs::InputError when B-bar is asked for where it does not apply (plane stress).
void check_volumetric(const Problem& problem);

/// kappa t C^T G C over the DOFs of `dofs`, upper triangle (added to the deviatoric stiffness).
Eigen::SparseMatrix<double> bbar_volumetric_stiffness(const Problem& problem, const DofMap& dofs,
                                                      const AssemblyStructure& structure);

/// The bulk modulus kappa = lambda + 2 mu / 3 of B-bar's split (3D and plane strain).
double bbar_bulk_modulus(const LameParameters& lame);
/// The Lame parameters of B-bar's deviatoric kernel: lambda' = -2 mu / 3, the same mu.
LameParameters bbar_deviatoric_lame(const LameParameters& lame);

/// The lambda the element kernel uses: lambda, or -2 mu / 3 under B-bar (deviatoric part only).
double kernel_lambda(const Problem& problem, double lambda, double mu);

/// B-bar stress from the displacement strain (in-plane in 2D) and the projected dilatation:
/// 2 mu dev(eps) + kappa theta_bar I with the 3D deviator (plane strain: eps_zz = 0, so szz is
/// kappa theta_bar - 2 mu tr(eps) / 3).
Eigen::Matrix3d bbar_stress(const Eigen::Matrix3d& strain, double projected_dilatation,
                            const Problem& problem);
/// The B-bar strain eps + (theta_bar - tr eps) / 3 I (3D trace; plane strain gets its zz entry):
/// bbar_stress is its Hooke stress.
Eigen::Matrix3d bbar_strain(const Eigen::Matrix3d& strain, double projected_dilatation,
                            const Problem& problem);
/// Energy density mu |dev eps|^2 + kappa / 2 theta_bar^2 (1/2 u^T K u integrates it).
double bbar_energy_density(const Eigen::Matrix3d& strain, double projected_dilatation,
                           const Problem& problem);

/// Pi div u of a solution, evaluated anywhere (post-processing).
class ProjectedDilatation {
 public:
  ProjectedDilatation(const Problem& problem,
                      const std::vector<std::vector<Eigen::Vector3d>>& displacements);
  double at(int patch, const nurbs::Param& u) const;

 private:
  VolumetricProjection projection_;
  Eigen::VectorXd coefficients_;
};

}  // namespace isospring::analysis::detail
