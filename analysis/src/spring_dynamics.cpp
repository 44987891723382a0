// Explicit (velocity Verlet) and implicit (backward Euler + Newton) spring-network integrators.
#include "isospring/analysis/spring_dynamics.hpp"

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "isospring/analysis/spring_mechanics.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::analysis {

namespace {

// Damping matrix sum c n n^T along the current directions: the velocity derivative of the
// (negated) damping forces.
Eigen::SparseMatrix<double> current_damping(const SpringNetwork& network,
                                            const Eigen::VectorXd& x) {
  SpringNetwork current = network;
  const int dim = network.dimension;
  for (size_t q = 0; q < current.positions.size(); ++q)
    for (int c = 0; c < dim; ++c)
      current.positions[q][c] = x[static_cast<Eigen::Index>(q) * dim + c];
  return rest_damping(current);
}

}  // namespace

SpringState rest_state(const SpringNetwork& network) {
  SpringState state;
  state.x = flat_positions(network);
  state.v = Eigen::VectorXd::Zero(state.x.size());
  return state;
}

void check_dynamics_input(const SpringNetwork& network, const SpringState& state) {
  const auto n = static_cast<Eigen::Index>(network.positions.size()) * network.dimension;
  if (state.x.size() != n || state.v.size() != n ||
      network.masses.size() != network.positions.size())
    throw nurbs::InputError("spring dynamics: state or masses do not match the network's " +
                            std::to_string(network.positions.size()) + " particles");
  for (size_t q = 0; q < network.masses.size(); ++q)
    if (!network.fixed[q] && !(network.masses[q] > 0.0))
      throw nurbs::InputError("spring dynamics: particle " + std::to_string(q) +
                              " is free but has mass " + std::to_string(network.masses[q]) +
                              "; give every free particle a positive mass or fix it");
}

double total_energy(const SpringNetwork& network, const SpringState& state,
                    const Eigen::VectorXd& f_ext) {
  const Eigen::VectorXd m = mass_diagonal(network);
  return 0.5 * state.v.dot(m.cwiseProduct(state.v)) + spring_energy(network, state.x) -
         f_ext.dot(state.x - flat_positions(network));
}

void step_velocity_verlet(const SpringNetwork& network, SpringState& state,
                          const Eigen::VectorXd& f_ext, double dt) {
  // Work vectors per thread: once they have the network's size a step allocates nothing (two
  // 256 KB temporaries per force evaluation at 10^4 particles went to mmap and page faults).
  thread_local Eigen::VectorXd inverse_mass, f_spring, f_damping, half;
  // 1/m on free DOFs, 0 on fixed ones (inverse_mass_diagonal without its temporaries).
  const int dim = network.dimension;
  inverse_mass.resize(state.x.size());
  for (size_t q = 0; q < network.masses.size(); ++q) {
    const bool fixed = q < network.fixed.size() && network.fixed[q];
    const double inverse = fixed ? 0.0 : 1.0 / network.masses[q];
    for (int c = 0; c < dim; ++c) inverse_mass[static_cast<Eigen::Index>(q) * dim + c] = inverse;
  }
  // Kick, drift, kick; the same expressions as acceleration(), so the same bits.
  spring_and_damping_forces(network, state.x, state.v, f_spring, f_damping);
  half = state.v + 0.5 * dt * (f_spring + f_damping + f_ext).cwiseProduct(inverse_mass);
  state.x += dt * half;
  spring_and_damping_forces(network, state.x, half, f_spring, f_damping);
  state.v = half + 0.5 * dt * (f_spring + f_damping + f_ext).cwiseProduct(inverse_mass);
}

int step_backward_euler(const SpringNetwork& network, SpringState& state,
                        const Eigen::VectorXd& f_ext, double dt,
                        const SpringSolveOptions& options) {
  // Unknown: end velocity v1 (free DOFs), x1 = x0 + dt v1.
  // R(v1) = M (v1 - v0) - dt (f_int(x1) + f_damp(x1, v1) + f_ext) = 0,
  // dR/dv1 = M + dt C(x1) + dt^2 K_t(x1)   (C: damping along the current directions).
  const FreeDofSet dofs(static_cast<int>(state.x.size()), fixed_dofs(network));
  const Eigen::VectorXd m = mass_diagonal(network);
  const Eigen::VectorXd x0 = state.x, v0 = state.v;
  Eigen::VectorXd v1 = v0;
  auto residual_at = [&](const Eigen::VectorXd& v) {
    const Eigen::VectorXd x = x0 + dt * v;
    return Eigen::VectorXd(dofs.restrict(
        Eigen::VectorXd(m.cwiseProduct(v - v0) -
                        dt * (spring_forces(network, x) + damping_forces(network, x, v) + f_ext))));
  };
  // Scale of the residual: the momentum change a step of the external and current forces gives.
  // Near equilibrium both vanish and the tolerance would fall below the round-off of the spring
  // forces (k (|d| - L0) loses eps k L0 per spring even when it balances the load), so Newton
  // could never stop. Floor: 1e-4 dt |(k L0)_springs| (with the default tolerance 1e-10 a residual
  // of 1e-14 of the springs' force scale, ~50 eps, still far below any physical momentum).
  double spring_scale = 0.0;
  for (const Spring& s : network.springs)
    spring_scale += (s.stiffness * s.rest_length) * (s.stiffness * s.rest_length);
  const double scale =
      std::max({dofs.restrict(Eigen::VectorXd(m.cwiseProduct(v0))).norm(),
                dt * dofs.restrict(Eigen::VectorXd(f_ext + spring_forces(network, x0))).norm(),
                1e-4 * dt * std::sqrt(spring_scale)});
  Eigen::VectorXd residual = residual_at(v1);
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver;
  for (int it = 0; it <= options.max_iterations; ++it) {
    if (residual.norm() <= options.tolerance * scale || scale == 0.0) {
      state.x = x0 + dt * v1;
      state.v = v1;
      return it;
    }
    if (it == options.max_iterations) break;
    const Eigen::VectorXd x1 = x0 + dt * v1;
    Eigen::SparseMatrix<double> jacobian =
        dt * dt * tangent_stiffness(network, x1) + dt * current_damping(network, x1);
    for (Eigen::Index d = 0; d < m.size(); ++d) jacobian.coeffRef(d, d) += m[d];
    solver.compute(dofs.restrict(jacobian));
    if (solver.info() != Eigen::Success)
      throw std::runtime_error("backward Euler: the step matrix M + dt C + dt^2 K is singular");
    v1 -= dofs.expand(solver.solve(residual));
    residual = residual_at(v1);
  }
  throw std::runtime_error("backward Euler: Newton did not converge in " +
                           std::to_string(options.max_iterations) +
                           " iterations; reduce the time step");
}

}  // namespace isospring::analysis
