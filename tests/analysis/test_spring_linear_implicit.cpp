// Linearly implicit backward Euler (constant prefactorised matrix): exact backward Euler where
// the spring force is linear, and second-order close to Newton backward Euler near rest.
#include <gtest/gtest.h>

#include <cmath>

#include "isospring/analysis/spring_dynamics.hpp"
#include "isospring/analysis/spring_linear_implicit.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::analysis {
namespace {

Spring spring(int i, int j, double k, double c, double length) {
  Spring s;
  s.i = i;
  s.j = j;
  s.stiffness = k;
  s.damping = c;
  s.rest_length = length;
  return s;
}

TEST(LinearImplicit, MatchesTheBackwardEulerRecursionOfALinearOscillator) {
  // One mass on one damped spring moving along the spring: f = -k x - c v exactly, so the
  // frozen-Jacobian step is backward Euler: m (v1 - v0) = dt (F - k x1 - c v1), x1 = x0 + dt v1.
  const double k = 50.0, m = 2.0, c = 3.0, dt = 0.02;
  SpringNetwork net;
  net.dimension = 2;
  net.positions = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0)};
  net.masses = {1.0, m};
  net.fixed = {true, false};
  net.springs.push_back(spring(0, 1, k, c, 1.0));
  LinearImplicitIntegrator integrator(net, dt);
  SpringState state = rest_state(net);
  state.x[2] += 0.01;
  double x = 0.01, v = 0.0;
  const Eigen::VectorXd load = (Eigen::VectorXd(4) << 0, 0, 0.4, 0).finished();
  for (int step = 0; step < 30; ++step) {
    v = (m * v + dt * (0.4 - k * x)) / (m + dt * c + dt * dt * k);
    x += dt * v;
    integrator.step(state, load);
    // Round-off of a 2x2 solve per step, accumulated over 30 steps.
    ASSERT_NEAR(state.x[2] - 1.0, x, 1e-13);
    ASSERT_NEAR(state.v[2], v, 1e-12);
  }
  EXPECT_EQ(state.x[0], 0.0);
  EXPECT_EQ(state.x[1], 0.0);
}

// Unit square, bottom fixed, edges and diagonals, unit masses, load F (1, -0.5) on the top pair.
double difference_to_newton(double load) {
  SpringNetwork net;
  net.dimension = 2;
  net.positions = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0),
                   Eigen::Vector3d(1, 1, 0)};
  net.masses = {1, 1, 1, 1};
  net.fixed = {true, true, false, false};
  const double d = std::sqrt(2.0);
  net.springs = {spring(0, 1, 100, 1, 1), spring(2, 3, 100, 1, 1), spring(0, 2, 100, 1, 1),
                 spring(1, 3, 100, 1, 1), spring(0, 3, 60, 1, d),  spring(1, 2, 60, 1, d)};
  const Eigen::VectorXd f = (Eigen::VectorXd(8) << 0, 0, 0, 0, 1, -0.5, 1, -0.5).finished() * load;
  LinearImplicitIntegrator integrator(net, 0.01);
  SpringState a = rest_state(net), b = rest_state(net);
  for (int step = 0; step < 20; ++step) {
    integrator.step(a, f);
    step_backward_euler(net, b, f, 0.01);
  }
  return (a.x - b.x).norm() / (b.x - rest_state(net).x).norm();
}

TEST(LinearImplicit, DiffersFromNewtonBackwardEulerAtSecondOrderInTheDisplacement) {
  // Freezing the Jacobian at rest drops the geometric stiffness and the rotation of the springs,
  // both O(u): the relative difference is O(u), so halving the load halves it (ratio 2 +- 10%).
  const double coarse = difference_to_newton(0.2), fine = difference_to_newton(0.1);
  EXPECT_GT(coarse, 1e-6);  // it is not accidentally the same integrator
  EXPECT_LT(coarse, 1e-2);
  EXPECT_NEAR(coarse / fine, 2.0, 0.2);
}

TEST(LinearImplicit, BadTimeStepIsInputError) {
  SpringNetwork net;
  net.dimension = 2;
  net.positions = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0)};
  net.masses = {1.0, 1.0};
  net.fixed = {true, false};
  net.springs.push_back(spring(0, 1, 1.0, 0.0, 1.0));
  EXPECT_THROW(LinearImplicitIntegrator(net, 0.0), nurbs::InputError);
  EXPECT_THROW(LinearImplicitIntegrator(net, -1.0), nurbs::InputError);
}

}  // namespace
}  // namespace isospring::analysis
