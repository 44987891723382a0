#pragma once
// Large-deformation elasticity: total Lagrangian St. Venant-Kirchhoff (SVK) on the same IGA
// spaces as the linear solver, with a Newton solve under dead loads (which also solves the
// neo-Hookean law of neo_hookean.hpp, NonlinearOptions::material).
//
//   F = I + grad_X u,  E = (F^T F - I) / 2,  S = lambda tr(E) I + 2 mu E,  P = F S
//   internal force  r_(a,i) = int P_ij dR_a/dX_j dV
//   tangent         K_(a,i),(b,k) = int [ lambda g_a,i g_b,k + mu (F F^T)_ik G_a.G_b
//                                         + mu g_b,i g_a,k + delta_ik G_a^T S G_b ] dV
// with G_a = dR_a/dX and g_a = F G_a. At u = 0 the tangent is the linear stiffness.
//
// Formulations: 3D solids; plane strain (F_33 = 1, exact); plane stress with the usual
// reduced lambda* = 2 lambda mu / (lambda + 2 mu) in the in-plane law (analysis::lame_parameters),
// exact for small strains but not the true plane-stress SVK at finite strain (that would need the
// thickness stretch as an extra unknown per point).
//
// Loads are dead (reference configuration): tractions, pressures (p times the REFERENCE normal),
// body forces, gravity and point loads come from assemble_load unchanged. Supports are imposed as
// in the linear solver (prescribed values scaled with the load factor while stepping).
#include <Eigen/Core>
#include <Eigen/Sparse>
#include <memory>
#include <string>
#include <vector>

#include "isospring/analysis/dof_map.hpp"
#include "isospring/analysis/elasticity.hpp"
#include "isospring/analysis/problem.hpp"

namespace isospring::analysis {

/// SVK internal force and consistent tangent of a problem's patches. Builds the element structure
/// once; each call is one pass over the elements (parallel over the element colouring). The
/// elements' basis gradients are evaluated at the first call and kept while they take at most
/// 256 MB (degree 3 in 3D: 98 KB per element, 106 MB at 8,019 DOFs); a tangent passed in again
/// is refilled in its own storage.
class SvkAssembler {
 public:
  SvkAssembler(const Problem& problem, const DofMap& dofs);
  ~SvkAssembler();
  SvkAssembler(const SvkAssembler&) = delete;
  SvkAssembler& operator=(const SvkAssembler&) = delete;

  /// Internal force r(u) (global DOF vector, `u` is one too) and, when `tangent` is not null, the
  /// tangent dr/du as an UPPER triangle (like assemble_stiffness). The material law uses `lame`
  /// (r and the tangent are linear in lambda and mu). Throws nurbs::InputError for an inverted
  /// reference parametrisation.
  Eigen::VectorXd internal_force(const Eigen::VectorXd& u, const LameParameters& lame,
                                 Eigen::SparseMatrix<double>* tangent = nullptr) const;
  /// The same pass split by material parameter: r(u) = lambda force_lambda + mu force_mu (the
  /// forces of S = tr(E) I and S = 2 E); the tangent, when requested, is for `lame`.
  void internal_force_parts(const Eigen::VectorXd& u, Eigen::VectorXd& force_lambda,
                            Eigen::VectorXd& force_mu, const LameParameters& lame,
                            Eigen::SparseMatrix<double>* tangent = nullptr) const;
  int num_dofs() const { return num_dofs_; }
  /// Threads of the element loop; 0 (the default): OpenMP's maximum at each call. Elements of one
  /// colour share no node and the colours run in order, so every sum is the same for any count.
  void set_threads(int threads) { threads_ = threads; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  int num_dofs_ = 0;
  int threads_ = 0;
};

/// The hyperelastic law of solve_static_nonlinear. Both reduce to the linear law (E, nu) at small
/// strain; neo-Hookean (neo_hookean.hpp) stays stable in large compression, where SVK softens.
enum class HyperelasticMaterial { kSaintVenantKirchhoff, kNeoHookean };

struct NonlinearOptions {
  HyperelasticMaterial material = HyperelasticMaterial::kSaintVenantKirchhoff;  // the law
  /// Converged when |r_free| <= tolerance * max(|f_free|, |r_constrained|) (r = f - internal force
  /// on the free DOFs; the reactions measure the load in displacement-driven problems).
  double tolerance = 1e-10;
  int max_iterations = 30;    // Newton iterations per load step
  int max_step_halvings = 8;  // a failed step is halved at most this often in a row
  int initial_steps = 1;      // equal load steps to start with
  int threads = 0;            // 0 = all
};

struct NonlinearLoadCaseResult {
  std::string id;
  Eigen::VectorXd displacement;                                     // global DOF vector
  std::vector<std::vector<Eigen::Vector3d>> control_displacements;  // [patch][control point]
  double max_displacement = 0;                                      // max |u| over control points
  int load_steps = 0;                                               // accepted load steps
  int iterations = 0;   // Newton iterations over all steps
  double residual = 0;  // final |r_free| / load measure
};

/// Validates the problem (as solve_static) and solves every load case with Newton (options.material
/// picks the law; neo-Hookean refuses plane stress with nurbs::InputError): full load
/// first, halving the load step after a failed step (no convergence in max_iterations, a
/// non-finite residual, or a singular tangent). The tangent is factorised with CHOLMOD's LLT and,
/// when it is indefinite (compression), with a simplicial LDLT. Throws std::runtime_error naming
/// the load case and the load factor reached when Newton fails.
std::vector<NonlinearLoadCaseResult> solve_static_nonlinear(const Problem& problem,
                                                            const NonlinearOptions& options = {});

}  // namespace isospring::analysis
