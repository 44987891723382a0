#pragma once
// Time integration of M x'' + C(x) x' + f_int(x) = f_ext for spring networks.
//
// Velocity Verlet is explicit and symplectic (undamped energy oscillates but does not drift;
// stable for dt below about 2 / omega_max). Backward Euler is implicit and unconditionally stable
// (it dissipates: an undamped oscillator's amplitude shrinks by 1/sqrt(1 + (omega dt)^2) a step).
// Fixed particles keep their position and zero velocity.
#include <Eigen/Core>

#include "isospring/analysis/spring_network.hpp"
#include "isospring/analysis/spring_static.hpp"

namespace isospring::analysis {

struct SpringState {
  Eigen::VectorXd x;  // positions, flat
  Eigen::VectorXd v;  // velocities, flat
};

/// Rest positions, zero velocity.
SpringState rest_state(const SpringNetwork& network);

/// Throws nurbs::InputError when a free particle has no positive mass (its acceleration would be
/// infinite) or the state's size does not match the network.
void check_dynamics_input(const SpringNetwork& network, const SpringState& state);

/// Total energy: kinetic + spring energy - f_ext . (x - rest).
double total_energy(const SpringNetwork& network, const SpringState& state,
                    const Eigen::VectorXd& f_ext);

/// One velocity-Verlet step (kick-drift-kick); damping uses the half-step velocity.
void step_velocity_verlet(const SpringNetwork& network, SpringState& state,
                          const Eigen::VectorXd& f_ext, double dt);

/// One backward-Euler step, solving for the end velocity with Newton's method (tangent stiffness
/// and damping along the current spring directions). Returns the Newton iterations; throws
/// std::runtime_error when Newton does not converge within options.max_iterations.
int step_backward_euler(const SpringNetwork& network, SpringState& state,
                        const Eigen::VectorXd& f_ext, double dt,
                        const SpringSolveOptions& options = {});

}  // namespace isospring::analysis
