#pragma once
// The reduced spring model with corotated forces: large rotations without the linear model's
// growth and stretch.
//
// ReducedSpringModel (spring_reduced_model.hpp) steps u = Phi q under the linear forces
// -Lambda q - C_r q'; a finite rotation is a strain to it. Here the same basis and the same
// linearly implicit step take the corotated forces of the network instead
// (spring_corotation.hpp), projected on the basis:
//   g_el(q, q') = Phi^T f_corot(X + Phi q, Phi q'),
//   (I + dt C_r + dt^2 Lambda) dq' = dt (g + g_el - dt Lambda q'),  q' += dq',  q += dt q'.
// With every rotation the identity g_el = -Lambda q - C_r q' and this is the linear model's
// step (the frozen rest Jacobian, as in LinearImplicitIntegrator, keeps the step matrix constant).
// The force is exactly zero for rigid motions of the positions it is given, and the difference
// from the linear model near rest is O(|u|^2).
//
// The basis. A corotated model in the span of linear modes locks: bending a beam by an angle t
// with linear modes alone stretches its fibres by O(t^2), which the rotation-extracted forces see
// as a strain and resist with the axial stiffness (measured: at 1 degree the corotated error was 4
// times the linear one's). So the basis gains modal derivatives [Barbic & James, "Real-time
// subspace integration for St. Venant-Kirchhoff deformable models", SIGGRAPH 2005]: for the
// lowest `derivative_modes` vectors (modes and load responses) v_i, v_j, the static responses
// psi_ij = -K^-1 (dK_t/dv_j) v_i (K_t the tangent stiffness; the derivative by central
// differences), the second-order shapes (the fibres' shortening) that large rotations need.
//
// Cost: the rotations need the particles' positions, so a step expands x = X + Phi q and
// projects the force back, O(n r) (plus O(n) polar decompositions and block products), against
// the linear model's O(r^2). Reading one particle's displacement stays O(r).
#include <Eigen/Core>
#include <algorithm>
#include <vector>

#include "isospring/analysis/spring_corotation.hpp"
#include "isospring/analysis/spring_reduced_model.hpp"

namespace isospring::analysis {

struct CorotatedModelOptions {
  ReducedModelOptions reduced;  // modes and load shapes, as for the linear model
  /// Lowest modes whose modal derivatives (pairwise, with the load shapes' responses) join the
  /// basis: m modes and l load shapes add (m + l)(m + l + 1) / 2 vectors. 0: none.
  int derivative_modes = 6;
};

/// The forces whose static responses are the modal derivatives of `vectors` (flat, network
/// DOFs): -(dK_t/dv_j) v_i for i <= j, by central differences of the tangent stiffness.
std::vector<Eigen::VectorXd> modal_derivative_forces(const SpringNetwork& network,
                                                     const Eigen::MatrixXd& vectors);

class CorotatedReducedModel {
 public:
  /// The basis (above), the linear reduced model on it (its step matrix; same errors as
  /// ReducedSpringModel, and nurbs::InputError for derivative_modes < 0) plus the network's
  /// corotated forces.
  CorotatedReducedModel(const SpringNetwork& network, double dt,
                        const CorotatedModelOptions& options);

  const ReducedSpringModel& linear() const { return linear_; }
  const CorotatedForces& corotation() const { return corotation_; }
  int size() const { return linear_.size(); }
  double dt() const { return linear_.dt(); }

  /// g_el at reduced coordinates q and rates qdot (qdot empty: no damping): O(n r).
  Eigen::VectorXd elastic_force(const Eigen::VectorXd& q, const Eigen::VectorXd& qdot) const;

  /// One step under the reduced external force g (ReducedSpringModel::reduce_force).
  void step(const Eigen::VectorXd& reduced_force);
  /// Force evaluations per step: 1 is the linearly implicit step above; k > 1 adds k - 1 chord
  /// iterations of backward Euler with the same matrix, v1 -= A^-1 (v1 - v0 - dt (g +
  /// g_el(q0 + dt v1, v1))), which converge at a rate ~ the rotation for the stiff directions.
  void set_iterations(int iterations) { iterations_ = std::max(1, iterations); }
  int iterations() const { return iterations_; }
  void reset();
  const Eigen::VectorXd& coordinates() const { return q_; }
  const Eigen::VectorXd& velocities() const { return qdot_; }
  Eigen::VectorXd displacement() const { return linear_.basis() * q_; }

  /// Static equilibrium g + g_el(q, 0) = 0 by Newton's method (Jacobian by central differences
  /// in the r coordinates, backtracking on |residual|), the load applied in `load_steps` equal
  /// increments. Returns q; throws std::runtime_error when Newton stalls above `tolerance`
  /// (relative to |g|; the force is evaluated at X + Phi q, so its round-off is ~1e-16 |X| / |u|
  /// relative: a tiny load needs a looser tolerance).
  Eigen::VectorXd static_coordinates(const Eigen::VectorXd& reduced_force, int load_steps = 10,
                                     double tolerance = 1e-10) const;

 private:
  ReducedSpringModel linear_;
  CorotatedForces corotation_;
  Eigen::VectorXd rest_;
  Eigen::VectorXd q_, qdot_;
  int iterations_ = 1;
  // Step scratch (no allocation per step after the first).
  mutable Eigen::VectorXd x_, v_, f_;
  mutable std::vector<Eigen::Matrix3d> rotations_;
};

}  // namespace isospring::analysis

namespace isospring::analysis {

/// The linear and the corotated reduced model against the full nonlinear network under one
/// constant load `force` (flat; every part of it is projected on the model's basis):
///  - static: the full network's Newton equilibrium (solve_spring_newton, `load_steps`
///    increments) against ReducedSpringModel::static_displacement and
///    CorotatedReducedModel::static_coordinates;
///  - motion: from rest, `steps` steps of the model's dt, the full network by backward Euler with
///    Newton on its exact forces (step_backward_euler) against both reduced models' steps.
/// Errors are %e_rms as in calibration: 100 sqrt(mean_i |u_ref,i - u_i|^2) / o_max over the
/// particles, o_max = max_i |u_ref,i|; for the motion the mean and the max run over particles and
/// steps. Throws std::runtime_error when a full-network or corotated static solve fails.
struct LargeRotationError {
  double static_linear = 0.0, static_corotated = 0.0;    // %e_rms
  double dynamic_linear = 0.0, dynamic_corotated = 0.0;  // %e_rms
  double static_o_max = 0.0, dynamic_o_max = 0.0;        // [m]
  /// Largest neighbourhood rotation (CorotatedForces::rotations) in the full static state [deg].
  double rotation_degrees = 0.0;
  /// The basis' own limit: %e_rms of the best (M-orthogonal) projection of the full static
  /// displacement on the basis.
  double static_best = 0.0;
  int steps = 0;
};
LargeRotationError large_rotation_error(const SpringNetwork& network, CorotatedReducedModel& model,
                                        const Eigen::VectorXd& force, int steps,
                                        int load_steps = 20);

/// %e_rms of u against u_ref (flat, `dimension` components per particle) with o_max = max
/// |u_ref,i|.
double percent_e_rms(const Eigen::VectorXd& u, const Eigen::VectorXd& u_ref, int dimension);

}  // namespace isospring::analysis
