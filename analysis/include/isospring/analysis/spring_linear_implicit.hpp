#pragma once
// Linearly implicit (semi-implicit) backward Euler with a constant, prefactorised matrix: the
// step a haptic loop can afford.
//
// step_backward_euler (spring_dynamics.hpp) runs Newton on the exact spring forces and rebuilds
// and refactorises M + dt C(x) + dt^2 K_t(x) every iteration (measured 8 steps/s at 10^3
// particles). Here the Jacobian is frozen at rest: A = M + dt C_0 + dt^2 K_0 (K_0, C_0: rest
// stiffness and damping, spring_mechanics.hpp) is factorised once (CHOLMOD supernodal LLT, A is
// symmetric positive definite for positive masses), and each step solves one system
//   A dv = dt (f_int(x0) + f_damp(x0, v0) + f_ext - dt K_0 v0),  v1 = v0 + dv, x1 = x0 + dt v1,
// i.e. one Newton iteration of backward Euler from v0 with the rest Jacobian [Baraff & Witkin,
// "Large steps in cloth simulation", SIGGRAPH 1998, eq. 6, with constant derivatives]. For a
// network that stays near rest (the linearised NMSM) this IS backward Euler (unconditionally
// stable, amplitude factor 1/sqrt(1 + (omega dt)^2) per step undamped); for large rotations it
// is first-order accurate but no longer unconditionally stable.
#include <Eigen/CholmodSupport>
#include <Eigen/Core>
#include <Eigen/Sparse>

#include "isospring/analysis/spring_dynamics.hpp"
#include "isospring/analysis/spring_network.hpp"
#include "isospring/analysis/spring_static.hpp"

namespace isospring::analysis {

class LinearImplicitIntegrator {
 public:
  /// kExact: the network's spring, cell and damper forces at the current state (above).
  /// kLinearised: the forces of the network linearised at rest, -K_0 (x - X) - C_0 v; the step
  /// is then exactly backward Euler of the linear model (the reference of the reduced model's
  /// projection error, spring_reduced_model.hpp).
  enum class Forces { kExact, kLinearised };
  /// Factorises M + dt C_0 + dt^2 K_0 on the free DOFs. Throws nurbs::InputError for dt <= 0 or
  /// a free particle without positive mass, std::runtime_error when the factorisation fails.
  LinearImplicitIntegrator(const SpringNetwork& network, double dt, Forces forces = Forces::kExact);
  LinearImplicitIntegrator(const LinearImplicitIntegrator&) = delete;
  LinearImplicitIntegrator& operator=(const LinearImplicitIntegrator&) = delete;

  double dt() const { return dt_; }
  /// One step (the network must be the one given to the constructor; fixed particles stay put).
  void step(SpringState& state, const Eigen::VectorXd& f_ext);

 private:
  const SpringNetwork& network_;
  double dt_;
  Forces forces_;
  FreeDofSet dofs_;
  Eigen::SparseMatrix<double> k0_;  // rest stiffness on the free DOFs (full storage)
  Eigen::SparseMatrix<double> c0_;  // rest damping on the free DOFs (kLinearised only)
  Eigen::VectorXd rest_;            // rest positions, flat
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Upper> solver_;
  Eigen::VectorXd rhs_, dv_, force_, damping_force_;  // work vectors (no allocation per step)
};

}  // namespace isospring::analysis
