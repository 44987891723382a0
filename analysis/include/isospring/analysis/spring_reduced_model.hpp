#pragma once
// A reduced (subspace) model of a calibrated spring network for haptic rates.
//
// Full-space stepping cannot reach 1 kHz at 10^4 particles on one core: a prefactorised global
// solve costs 6-12 ms there. The calibrated network's rest stiffness K and damping C are
// constant, so its small-deformation dynamics M u'' + C u' + K u = f live well in a few
// vectors: the lowest natural modes (K phi = omega^2 M phi) plus, optionally, the static
// responses K^-1 f_i of the loads the application applies (load-dependent Ritz vectors: with
// them the static response to those loads is exact, which modes alone reach only slowly).
// The basis V is M-orthonormalised and diagonalised in its span (Rayleigh-Ritz), so
//   Phi^T M Phi = I,  Phi^T K Phi = Lambda (diagonal),  C_r = Phi^T C Phi (dense, small),
// and u = Phi q. A step is the same linearly implicit backward Euler as the full model's
// LinearImplicitIntegrator (spring_linear_implicit.hpp), projected:
//   (I + dt C_r + dt^2 Lambda) dq' = dt (g - Lambda q - C_r q' - dt Lambda q'),
//   q' += dq', q += dt q',  g = Phi^T f_ext,
// so the reduced model differs from the full one only by the projection (and, at large
// deformation, by the full model's nonlinear spring forces). A step costs O(r^2) whatever the
// network's size; forces and displacements of single particles cost O(r) each; the whole field
// O(n r).
//
// K is rest_stiffness(network): springs, cell and strain-point terms, linearised at rest. Limit:
// linear about the rest state (rotations must stay small); reduction_error measures what that
// costs against the full nonlinear network. CorotatedReducedModel (spring_reduced_corotated.hpp)
// is the large-rotation variant.
#include <Eigen/Core>
#include <vector>

#include "isospring/analysis/spring_network.hpp"

namespace isospring::analysis {

struct ReducedModelOptions {
  int modes = 24;  // lowest natural modes of the supported network
  /// Flat force vectors (network DOFs) whose static responses join the basis; fixed particles'
  /// components are ignored. Needs a supported network (K positive definite).
  std::vector<Eigen::VectorXd> load_shapes;
  /// Relative tolerance of the Lanczos Ritz values: the Rayleigh-Ritz step diagonalises the
  /// span again, so the modes need not be converged to round-off.
  double mode_tolerance = 1e-8;
};

class ReducedSpringModel {
 public:
  /// Builds the basis (Spectra shift-invert Lanczos on the free DOFs, CHOLMOD for the load
  /// shapes) and factorises the reduced step matrix. Throws nurbs::InputError for dt <= 0, a
  /// free particle without positive mass, a mode count outside 0 .. free DOFs - 1, no vectors
  /// at all, or a load shape of the wrong size or not finite;
  /// std::runtime_error when K is singular while load shapes are asked for.
  ReducedSpringModel(const SpringNetwork& network, double dt, const ReducedModelOptions& options);

  int size() const { return static_cast<int>(lambda_.size()); }
  double dt() const { return dt_; }
  int dimension() const { return dim_; }
  /// omega^2 of the basis vectors [1/s^2], ascending (Ritz values: the lowest are the network's
  /// natural frequencies when enough modes are asked for).
  const Eigen::VectorXd& eigenvalues() const { return lambda_; }
  /// Basis on every network DOF (rows of fixed DOFs are zero), M-orthonormal.
  const Eigen::MatrixXd& basis() const { return basis_; }
  /// C_r = Phi^T C Phi and (I + dt C_r + dt^2 Lambda)^-1: with the basis and the eigenvalues,
  /// everything an engine needs to run the step (io/export_reduced.hpp).
  const Eigen::MatrixXd& damping() const { return damping_; }
  const Eigen::MatrixXd& step_inverse() const { return step_inverse_; }

  /// g = Phi^T f for a flat force on the network's DOFs: O(n r).
  Eigen::VectorXd reduce_force(const Eigen::VectorXd& force) const;
  /// g of a force on one particle (components beyond the dimension ignored): O(r).
  Eigen::VectorXd reduce_particle_force(int particle, const Eigen::Vector3d& force) const;

  /// One step under the reduced force g (size()).
  void step(const Eigen::VectorXd& reduced_force);
  /// Back to rest, at zero velocity.
  void reset();
  const Eigen::VectorXd& coordinates() const { return q_; }
  const Eigen::VectorXd& velocities() const { return qdot_; }

  /// Displacement of every network DOF (flat): O(n r).
  Eigen::VectorXd displacement() const;
  /// Displacement of one particle (z = 0 in 2D): O(r).
  Eigen::Vector3d particle_displacement(int particle) const;
  /// Static response Phi Lambda^-1 Phi^T f (flat): exact for the load shapes.
  Eigen::VectorXd static_displacement(const Eigen::VectorXd& force) const;

 private:
  int dim_ = 3;
  double dt_ = 0.0;
  Eigen::MatrixXd basis_;         // network DOFs x r
  Eigen::VectorXd lambda_;        // omega^2
  Eigen::MatrixXd damping_;       // C_r
  Eigen::MatrixXd step_inverse_;  // (I + dt C_r + dt^2 Lambda)^-1
  Eigen::VectorXd q_, qdot_;
};

/// The reduced model against the full network under one constant load `force` (flat), all
/// started at rest and run for `steps` steps of the model's dt:
///  - the static response against the full linear solve;
///  - the motion against the full network linearised at rest (LinearImplicitIntegrator,
///    Forces::kLinearised): the same scheme on every DOF, so this is the projection's own error;
///  - the motion against the full network with its exact (nonlinear) forces
///    (Forces::kExact): projection plus linearisation. The frozen-Jacobian scheme is not
///    unconditionally stable at large rotations: when that run leaves every bound (a
///    displacement 1e3 x the linear run's largest, or not finite), `exact_diverged` is set and
///    the exact figures are NaN.
struct ReductionError {
  double static_relative = 0.0;      // |u_r - u| / |u| of the static responses
  double projection_relative = 0.0;  // rms over steps of |u_r - u_lin| / rms of |u_lin|
  double dynamic_relative = 0.0;     // rms over steps of |u_r - u| / rms of |u| (exact forces)
  double dynamic_max = 0.0;          // max over steps and particles of |u_r - u| [m]
  bool exact_diverged = false;
  int steps = 0;
};
ReductionError reduction_error(const SpringNetwork& network, ReducedSpringModel& model,
                               const Eigen::VectorXd& force, int steps);

}  // namespace isospring::analysis
