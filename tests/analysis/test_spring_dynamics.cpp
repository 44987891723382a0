// Integrators on one mass on one spring (x'' = -omega^2 x along the spring), where the exact and
// the discrete solutions are known in closed form.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "isospring/analysis/spring_dynamics.hpp"
#include "isospring/analysis/spring_mechanics.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::analysis {
namespace {

// Particle 0 fixed at the origin, particle 1 of mass m at (L, 0), spring k along x (2D).
SpringNetwork oscillator(double k, double m, double c = 0.0) {
  SpringNetwork net;
  net.dimension = 2;
  net.positions = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1.0, 0, 0)};
  net.masses = {1.0, m};
  net.fixed = {true, false};
  Spring s;
  s.i = 0;
  s.j = 1;
  s.stiffness = k;
  s.damping = c;
  s.rest_length = 1.0;
  net.springs.push_back(s);
  return net;
}

TEST(SpringDynamics, VelocityVerletConservesEnergyWithoutDrift) {
  const double k = 4.0, m = 1.0, omega = 2.0, dt = 0.01, amplitude = 0.1;
  const SpringNetwork net = oscillator(k, m);
  SpringState state = rest_state(net);
  state.x[2] += amplitude;
  const Eigen::VectorXd no_load = Eigen::VectorXd::Zero(4);
  check_dynamics_input(net, state);
  const double e0 = total_energy(net, state, no_load);
  const int steps_per_period = static_cast<int>(std::round(2 * M_PI / omega / dt));
  double first_period = 0.0, last_period = 0.0;
  const int periods = 50;
  for (int step = 1; step <= periods * steps_per_period; ++step) {
    step_velocity_verlet(net, state, no_load, dt);
    const double error = std::abs(total_energy(net, state, no_load) - e0) / e0;
    if (step <= steps_per_period) first_period = std::max(first_period, error);
    if (step > (periods - 1) * steps_per_period) last_period = std::max(last_period, error);
  }
  // Verlet's shadow energy: the oscillation is O((omega dt)^2 / 4) = 1e-4 and does not grow.
  EXPECT_LT(first_period, 0.25 * (omega * dt) * (omega * dt) * 1.01);
  EXPECT_LT(last_period, first_period * 1.01);
  // Phase error after 50 periods: omega_h = (2/dt) asin(omega dt / 2) -> cos(omega_h t).
  const double t = periods * steps_per_period * dt;
  const double omega_h = 2.0 / dt * std::asin(omega * dt / 2.0);
  EXPECT_NEAR(state.x[2] - 1.0, amplitude * std::cos(omega_h * t), 1e-4 * amplitude);
}

TEST(SpringDynamics, BackwardEulerDecaysEnergyByExactFactor) {
  // Scaled state (omega x, v) is multiplied by a rotation times 1/sqrt(1 + h^2), h = omega dt:
  // the energy falls by exactly 1/(1 + h^2) per step.
  const double k = 9.0, m = 1.0, dt = 0.05, h = 3.0 * dt;
  const SpringNetwork net = oscillator(k, m);
  SpringState state = rest_state(net);
  state.x[2] += 0.05;
  const Eigen::VectorXd no_load = Eigen::VectorXd::Zero(4);
  double energy = total_energy(net, state, no_load);
  for (int step = 0; step < 40; ++step) {
    step_backward_euler(net, state, no_load, dt);
    const double next = total_energy(net, state, no_load);
    EXPECT_NEAR(next / energy, 1.0 / (1.0 + h * h), 1e-9);
    energy = next;
  }
}

TEST(SpringDynamics, BackwardEulerWithDampingMatchesTheLinearRecursion) {
  const double k = 50.0, m = 2.0, c = 3.0, dt = 0.02;
  const SpringNetwork net = oscillator(k, m, c);
  SpringState state = rest_state(net);
  state.x[2] += 0.01;
  double x = 0.01, v = 0.0;
  const Eigen::VectorXd load = (Eigen::VectorXd(4) << 0, 0, 0.4, 0).finished();
  for (int step = 0; step < 30; ++step) {
    // m (v1 - v0) = dt (-k x1 - c v1 + F), x1 = x0 + dt v1.
    v = (m * v + dt * (0.4 - k * x)) / (m + dt * c + dt * dt * k);
    x += dt * v;
    step_backward_euler(net, state, load, dt);
    ASSERT_NEAR(state.x[2] - 1.0, x, 1e-12);
    ASSERT_NEAR(state.v[2], v, 1e-10);
  }
  EXPECT_EQ(state.x[0], 0.0);  // the fixed particle does not move
}

TEST(SpringDynamics, DampedVerletSettlesToStaticSolution) {
  SpringNetwork net = oscillator(20.0, 0.5);
  assign_damping_ratio(net, 0.3);
  SpringState state = rest_state(net);
  const Eigen::VectorXd load = (Eigen::VectorXd(4) << 0, 0, 1.0, 0).finished();
  for (int step = 0; step < 4000; ++step) step_velocity_verlet(net, state, load, 0.005);
  EXPECT_NEAR(state.x[2] - 1.0, 1.0 / 20.0, 1e-9);
}

// A damping ratio means what an engineer expects: a lone spring of stiffness k with one end held
// and mass m at the other, given zeta, decays with the logarithmic decrement
// delta = 2 pi zeta / sqrt(1 - zeta^2) between successive peaks. The motion stays along the
// spring, so the model is exactly the linear damped oscillator. Velocity Verlet at
// omega dt = 6e-4 and peaks located by a parabola through the three samples around each maximum
// leave errors of order (omega dt)^2 = 4e-7 relative, far inside the 1e-4 asserted; treating the
// held end's mass as part of a two-body reduced mass instead would give zeta 0.041, not 0.05.
TEST(SpringDynamics, DampingRatioGivesTheLogarithmicDecrement) {
  const double k = 20.0, m = 0.5, zeta = 0.05, dt = 1e-4;
  SpringNetwork net = oscillator(k, m);
  assign_damping_ratio(net, zeta);
  SpringState state = rest_state(net);
  state.x[2] += 0.1;
  const Eigen::VectorXd no_load = Eigen::VectorXd::Zero(4);
  std::vector<double> peaks;
  double prev2 = 0.1, prev1 = 0.1;
  for (int step = 0; step < 60000 && peaks.size() < 4; ++step) {
    step_velocity_verlet(net, state, no_load, dt);
    const double now = state.x[2] - 1.0;
    if (step > 1 && prev1 > prev2 && prev1 >= now) {
      // Vertex of the parabola through the three samples.
      const double a = 0.5 * (prev2 - 2 * prev1 + now), b = 0.5 * (now - prev2);
      peaks.push_back(prev1 - b * b / (4 * a));
    }
    prev2 = prev1;
    prev1 = now;
  }
  ASSERT_EQ(peaks.size(), 4u);
  for (size_t n = 0; n + 1 < peaks.size(); ++n) {
    const double delta = std::log(peaks[n] / peaks[n + 1]);
    EXPECT_NEAR(delta / std::sqrt(4 * M_PI * M_PI + delta * delta), zeta, 1e-4 * zeta);
  }
}

// Two free masses: the spring's relative coordinate is an oscillator with the reduced mass.
TEST(SpringDynamics, DampingRatioOfTwoFreeMassesUsesTheReducedMass) {
  SpringNetwork net = oscillator(20.0, 0.5);
  net.fixed = {false, false};
  net.masses = {1.0, 0.5};
  assign_damping_ratio(net, 0.05);
  EXPECT_NEAR(net.springs[0].damping, 2 * 0.05 * std::sqrt(20.0 * (1.0 * 0.5 / 1.5)), 1e-15);
}

TEST(SpringDynamics, MasslessFreeParticleIsInputError) {
  SpringNetwork net = oscillator(1.0, 0.0);
  EXPECT_THROW(check_dynamics_input(net, rest_state(net)), nurbs::InputError);
  EXPECT_THROW(assign_damping_alpha(net, 0.0), nurbs::InputError);
}

}  // namespace
}  // namespace isospring::analysis
