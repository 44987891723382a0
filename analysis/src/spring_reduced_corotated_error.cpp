// Linear and corotated reduced models against the full nonlinear network at large rotation.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>

#include "isospring/analysis/spring_dynamics.hpp"
#include "isospring/analysis/spring_mechanics.hpp"
#include "isospring/analysis/spring_reduced_corotated.hpp"
#include "isospring/analysis/spring_static.hpp"

namespace isospring::analysis {
namespace {

std::string scientific(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

double largest_particle_norm(const Eigen::VectorXd& u, int dim) {
  double largest = 0.0;
  for (Eigen::Index p = 0; p < u.size() / dim; ++p)
    largest = std::max(largest, u.segment(p * dim, dim).norm());
  return largest;
}

double largest_rotation_degrees(const CorotatedForces& corotation, const Eigen::VectorXd& x) {
  std::vector<Eigen::Matrix3d> rotations;
  corotation.rotations(x, rotations);
  double largest = 0.0;
  for (const Eigen::Matrix3d& r : rotations)
    largest = std::max(largest, std::acos(std::clamp(0.5 * (r.trace() - 1.0), -1.0, 1.0)));
  return largest * 180.0 / std::numbers::pi;
}

// Static figures: the full network's equilibrium against both reduced models'.
void static_errors(const SpringNetwork& network, const CorotatedReducedModel& model,
                   const Eigen::VectorXd& force, int load_steps, LargeRotationError& error) {
  const int dim = network.dimension;
  SpringSolveOptions options;
  options.load_steps = load_steps;
  // 1e-9: the round-off floor of the residual of a stiff network under a small load is near the
  // default 1e-10.
  options.tolerance = 1e-9;
  const SpringSolveResult full = solve_spring_newton(network, force, options);
  if (!full.converged)
    throw std::runtime_error(
        "large_rotation_error: the full network's Newton solve did not "
        "converge (relative residual " +
        scientific(full.relative_residual) + "); use more load steps");
  const Eigen::VectorXd& u = full.displacement;
  error.static_o_max = largest_particle_norm(u, dim);
  error.rotation_degrees =
      largest_rotation_degrees(model.corotation(), flat_positions(network) + u);
  const ReducedSpringModel& linear = model.linear();
  error.static_linear = percent_e_rms(linear.static_displacement(force), u, dim);
  const Eigen::VectorXd q = model.static_coordinates(linear.reduce_force(force), load_steps);
  error.static_corotated = percent_e_rms(linear.basis() * q, u, dim);
  // Phi is M-orthonormal, so Phi Phi^T M u is the M-orthogonal projection.
  const Eigen::VectorXd mu = mass_diagonal(network).cwiseProduct(u);
  error.static_best = percent_e_rms(linear.basis() * (linear.basis().transpose() * mu), u, dim);
}

}  // namespace

double percent_e_rms(const Eigen::VectorXd& u, const Eigen::VectorXd& u_ref, int dimension) {
  const double o_max = largest_particle_norm(u_ref, dimension);
  const double particles = static_cast<double>(u_ref.size() / dimension);
  return o_max > 0.0 ? 100.0 * std::sqrt((u - u_ref).squaredNorm() / particles) / o_max : 0.0;
}

LargeRotationError large_rotation_error(const SpringNetwork& network, CorotatedReducedModel& model,
                                        const Eigen::VectorXd& force, int steps, int load_steps) {
  LargeRotationError error;
  error.steps = steps;
  static_errors(network, model, force, load_steps, error);

  const int dim = network.dimension;
  ReducedSpringModel linear = model.linear();  // a copy: its state is stepped here
  linear.reset();
  model.reset();
  SpringState full = rest_state(network);
  const Eigen::VectorXd rest = full.x, g = linear.reduce_force(force);
  double linear_squared = 0.0, corotated_squared = 0.0;
  for (int s = 0; s < steps; ++s) {
    step_backward_euler(network, full, force, model.dt());
    linear.step(g);
    model.step(g);
    const Eigen::VectorXd u = full.x - rest;
    error.dynamic_o_max = std::max(error.dynamic_o_max, largest_particle_norm(u, dim));
    linear_squared += (linear.displacement() - u).squaredNorm();
    corotated_squared += (model.displacement() - u).squaredNorm();
  }
  const double samples = static_cast<double>(steps) * static_cast<double>(rest.size() / dim);
  if (error.dynamic_o_max > 0.0) {
    error.dynamic_linear = 100.0 * std::sqrt(linear_squared / samples) / error.dynamic_o_max;
    error.dynamic_corotated = 100.0 * std::sqrt(corotated_squared / samples) / error.dynamic_o_max;
  }
  model.reset();
  return error;
}

}  // namespace isospring::analysis
