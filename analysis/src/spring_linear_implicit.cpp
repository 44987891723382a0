// Semi-implicit backward Euler with the rest Jacobian factorised once.
#include "isospring/analysis/spring_linear_implicit.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "isospring/analysis/spring_mechanics.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::analysis {

LinearImplicitIntegrator::LinearImplicitIntegrator(const SpringNetwork& network, double dt,
                                                   Forces forces)
    : network_(network),
      dt_(dt),
      forces_(forces),
      dofs_(static_cast<int>(network.positions.size()) * network.dimension, fixed_dofs(network)) {
  if (!(dt > 0.0) || !std::isfinite(dt))
    throw nurbs::InputError("linear implicit integrator: time step " + std::to_string(dt) +
                            " is not a positive number");
  check_dynamics_input(network, rest_state(network));
  k0_ = dofs_.restrict(rest_stiffness(network));
  c0_ = dofs_.restrict(rest_damping(network));
  Eigen::SparseMatrix<double> a = dt * dt * k0_ + dt * c0_;
  if (forces_ == Forces::kExact) c0_.resize(0, 0);  // only the linearised forces need it
  rest_ = flat_positions(network);
  const Eigen::VectorXd m = dofs_.restrict(mass_diagonal(network));
  for (Eigen::Index d = 0; d < m.size(); ++d) a.coeffRef(d, d) += m[d];
  solver_.cholmod().print = 0;
  solver_.compute(a);
  if (solver_.info() != Eigen::Success)
    throw std::runtime_error(
        "linear implicit integrator: M + dt C + dt^2 K is not positive definite");
}

void LinearImplicitIntegrator::step(SpringState& state, const Eigen::VectorXd& f_ext) {
  const Eigen::VectorXd v_free = dofs_.restrict(state.v);
  if (forces_ == Forces::kExact) {
    // One pass for both forces; (f_spring + f_ext) + f_damping as before.
    spring_and_damping_forces(network_, state.x, state.v, force_, damping_force_);
    force_ += f_ext;
    force_ += damping_force_;
    rhs_ = dofs_.restrict(force_);
  } else {
    rhs_ = dofs_.restrict(f_ext) - k0_ * dofs_.restrict(Eigen::VectorXd(state.x - rest_)) -
           c0_ * v_free;
  }
  rhs_ = dt_ * (rhs_ - dt_ * (k0_ * v_free));
  dv_ = solver_.solve(rhs_);
  for (int f = 0; f < dofs_.num_free(); ++f) {
    const int dof = dofs_.free_dofs()[static_cast<size_t>(f)];
    state.v[dof] += dv_[f];
    state.x[dof] += dt_ * state.v[dof];
  }
}

}  // namespace isospring::analysis
