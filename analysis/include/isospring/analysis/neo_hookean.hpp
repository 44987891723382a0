#pragma once
// Large-deformation elasticity with a compressible neo-Hookean material (total Lagrangian), in
// the form of Abaqus and CalculiX (*HYPERELASTIC, NEO HOOKE):
//
//   W = C10 (I1bar - 3) + (J - 1)^2 / D1,   I1bar = J^(-2/3) tr(F^T F),  J = det F,
//   C10 = mu / 2, D1 = 2 / K   (mu, K: the small-strain shear and bulk moduli of E and nu)
//   P = dW/dF = mu J^(-2/3) (F - (I1 / 3) H) + K J (J - 1) H,   H = F^-T
//   A_iJkL = dP_iJ/dF_kL
//          = mu J^(-2/3) [ d_ik d_JL - 2/3 (F_iJ H_kL + H_iJ F_kL) + 2/9 I1 H_iJ H_kL
//                          + 1/3 I1 H_iL H_kJ ]
//            + K [ J (2J - 1) H_iJ H_kL - J (J - 1) H_iL H_kJ ]
//   internal force  r_(a,i) = int P_iJ G_a,J dV,   tangent  K_(a,i),(b,k) = int G_a,J A_iJkL G_b,L
//   dV
// with G_a = dR_a/dX. At F = I, A is Hooke's law with lambda = K - 2 mu / 3: the tangent at u = 0
// is the linear stiffness.
//
// Formulations: 3D solids and plane strain (F_33 = 1: the same formulas with the in-plane block
// of F and I1 = tr(C_2x2) + 1, exact). Plane stress is refused: its thickness stretch would be an
// extra unknown per point (unlike SVK's small-strain convention there is no standard reduced law).
#include <Eigen/Core>
#include <Eigen/Sparse>
#include <memory>

#include "isospring/analysis/dof_map.hpp"
#include "isospring/analysis/problem.hpp"

namespace isospring::analysis {

/// Shear and bulk moduli of the neo-Hookean law (C10 = shear / 2, D1 = 2 / bulk).
struct NeoHookeanParameters {
  double shear = 0.0;  // mu = E / (2 (1 + nu))
  double bulk = 0.0;   // K = E / (3 (1 - 2 nu))
};

/// The moduli of a material whose small-strain limit is its linear law (E, nu). Throws
/// nurbs::InputError for plane stress (not supported, see above) and for nu outside (-1, 0.5) or
/// E <= 0.
NeoHookeanParameters neo_hookean_parameters(const Material& material, Formulation formulation);

/// Neo-Hookean internal force and consistent tangent of a problem's patches. Builds the element
/// structure once; each call is one pass over the elements (parallel over the element colouring,
/// the same sums for any thread count).
class NeoHookeanAssembler {
 public:
  /// Throws nurbs::InputError for plane stress.
  NeoHookeanAssembler(const Problem& problem, const DofMap& dofs);
  ~NeoHookeanAssembler();
  NeoHookeanAssembler(const NeoHookeanAssembler&) = delete;
  NeoHookeanAssembler& operator=(const NeoHookeanAssembler&) = delete;

  /// Internal force r(u) (global DOF vectors) and, when `tangent` is not null, dr/du as an UPPER
  /// triangle (like assemble_stiffness). Where the deformation inverts or flattens the material
  /// (J <= 0 at a quadrature point) W is undefined: the force is NaN there (Newton then cuts its
  /// load step). Throws nurbs::InputError for an inverted reference parametrisation.
  Eigen::VectorXd internal_force(const Eigen::VectorXd& u, const NeoHookeanParameters& moduli,
                                 Eigen::SparseMatrix<double>* tangent = nullptr) const;
  int num_dofs() const { return num_dofs_; }
  /// Threads of the element loop; 0 (the default): OpenMP's maximum at each call.
  void set_threads(int threads) { threads_ = threads; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  int num_dofs_ = 0;
  int threads_ = 0;
};

}  // namespace isospring::analysis
