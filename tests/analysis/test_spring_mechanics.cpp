// Spring-network mechanics against closed forms (series springs), finite differences (forces vs
// energy, tangent stiffness vs forces) and the linear limit of Newton's method.
#include <gtest/gtest.h>

#include <random>

#include "isospring/analysis/spring_mechanics.hpp"
#include "isospring/analysis/spring_static.hpp"

namespace isospring::analysis {
namespace {

// Particles on the x axis, particle 0 fixed, springs k[s] between s and s+1 (3D).
SpringNetwork chain(const std::vector<double>& stiffness, double spacing) {
  SpringNetwork net;
  net.dimension = 3;
  for (size_t q = 0; q <= stiffness.size(); ++q)
    net.positions.emplace_back(spacing * static_cast<double>(q), 0.0, 0.0);
  net.masses.assign(net.positions.size(), 1.0);
  net.fixed.assign(net.positions.size(), false);
  net.fixed[0] = true;
  for (size_t s = 0; s < stiffness.size(); ++s) {
    Spring spring;
    spring.i = static_cast<int>(s);
    spring.j = static_cast<int>(s) + 1;
    spring.stiffness = stiffness[s];
    spring.rest_length = spacing;
    net.springs.push_back(spring);
  }
  return net;
}

// The y and z components of every particle: a chain only resists motion along its axis.
std::vector<int> transverse_dofs(const SpringNetwork& net) {
  std::vector<int> dofs;
  for (size_t q = 0; q < net.positions.size(); ++q) {
    dofs.push_back(static_cast<int>(q) * 3 + 1);
    dofs.push_back(static_cast<int>(q) * 3 + 2);
  }
  return dofs;
}

// A 2D n x n grid with edge and diagonal springs (the NMSM cell pattern), left column fixed.
SpringNetwork grid_2d(int n, double h) {
  SpringNetwork net;
  net.dimension = 2;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) net.positions.emplace_back(h * i, h * j, 0.0);
  net.masses.assign(net.positions.size(), 0.5);
  net.fixed.assign(net.positions.size(), false);
  for (int j = 0; j < n; ++j) net.fixed[j * n] = true;
  auto add = [&](int a, int b, double k) {
    Spring s;
    s.i = a;
    s.j = b;
    s.stiffness = k;
    s.rest_length = (net.positions[a] - net.positions[b]).norm();
    net.springs.push_back(s);
  };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int q = j * n + i;
      if (i + 1 < n) add(q, q + 1, 10.0);
      if (j + 1 < n) add(q, q + n, 12.0);
      if (i + 1 < n && j + 1 < n) {
        add(q, q + n + 1, 7.0);
        add(q + 1, q + n, 6.0);
      }
    }
  return net;
}

TEST(SpringMechanics, SingleSpringLinearAndNewtonGiveHookesLaw) {
  const SpringNetwork net = chain({250.0}, 0.3);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(6);
  f[3] = 5.0;  // pulls particle 1 along the spring
  const auto linear = solve_spring_linear(net, f, transverse_dofs(net));
  EXPECT_NEAR(linear.displacement[3], 5.0 / 250.0, 1e-15);
  // Along its axis a spring is exactly linear, so Newton agrees and converges at once.
  const auto newton = solve_spring_newton(net, f, {}, transverse_dofs(net));
  EXPECT_TRUE(newton.converged);
  EXPECT_NEAR(newton.displacement[3], 5.0 / 250.0, 1e-14);
  EXPECT_NEAR(spring_energy(net, flat_positions(net) + linear.displacement),
              0.5 * 5.0 * 5.0 / 250.0, 1e-14);
}

TEST(SpringMechanics, ChainUnderTipLoadIsSeriesSprings) {
  const std::vector<double> k = {100.0, 40.0, 250.0, 80.0};
  const SpringNetwork net = chain(k, 0.5);
  const double force = 3.0;
  Eigen::VectorXd f = Eigen::VectorXd::Zero(static_cast<int>(net.positions.size()) * 3);
  f[static_cast<int>(k.size()) * 3] = force;
  const auto newton = solve_spring_newton(net, f, {}, transverse_dofs(net));
  ASSERT_TRUE(newton.converged);
  double compliance = 0.0;
  for (size_t s = 0; s < k.size(); ++s) {
    compliance += 1.0 / k[s];
    // Every spring carries the full load, so particle s+1 has moved force * sum_{t<=s} 1/k_t.
    EXPECT_NEAR(newton.displacement[static_cast<int>(s + 1) * 3], force * compliance, 1e-13);
  }
}

TEST(SpringMechanics, UnsupportedNetworkIsReportedAsMechanism) {
  const SpringNetwork net = chain({100.0}, 1.0);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(6);
  f[4] = 1.0;  // transverse: a single spring has no stiffness across itself
  EXPECT_THROW(solve_spring_linear(net, f), std::runtime_error);
}

// A random 3D network away from rest (lengths differ from rest lengths) to test derivatives.
SpringNetwork random_network(std::mt19937& rng) {
  std::uniform_real_distribution<double> coord(-1.0, 1.0), stiff(1.0, 100.0), ratio(0.6, 1.4);
  SpringNetwork net;
  net.dimension = 3;
  for (int q = 0; q < 6; ++q) net.positions.emplace_back(coord(rng), coord(rng), coord(rng));
  net.masses.assign(6, 1.0);
  net.fixed.assign(6, false);
  for (int i = 0; i < 6; ++i)
    for (int j = i + 1; j < 6; ++j) {
      Spring s;
      s.i = i;
      s.j = j;
      s.stiffness = stiff(rng);
      s.rest_length = ratio(rng) * (net.positions[i] - net.positions[j]).norm();
      net.springs.push_back(s);
    }
  return net;
}

TEST(SpringMechanics, ForcesAreMinusEnergyGradient) {
  std::mt19937 rng(7);
  const SpringNetwork net = random_network(rng);
  const Eigen::VectorXd x = flat_positions(net);
  const Eigen::VectorXd f = spring_forces(net, x);
  const double h = 1e-6;
  for (int d = 0; d < x.size(); ++d) {
    Eigen::VectorXd xp = x, xm = x;
    xp[d] += h;
    xm[d] -= h;
    const double gradient = (spring_energy(net, xp) - spring_energy(net, xm)) / (2 * h);
    // Central differences: O(h^2) truncation, O(eps E / h) round-off: about 1e-8 here.
    EXPECT_NEAR(f[d], -gradient, 1e-7 * (1.0 + std::abs(gradient)));
  }
}

TEST(SpringMechanics, TangentStiffnessMatchesFiniteDifferencesOfForces) {
  std::mt19937 rng(11);
  const SpringNetwork net = random_network(rng);
  const Eigen::VectorXd x = flat_positions(net);
  const Eigen::MatrixXd k = Eigen::MatrixXd(tangent_stiffness(net, x));
  const double h = 1e-6;
  double worst = 0.0;
  for (int d = 0; d < x.size(); ++d) {
    Eigen::VectorXd xp = x, xm = x;
    xp[d] += h;
    xm[d] -= h;
    const Eigen::VectorXd column = -(spring_forces(net, xp) - spring_forces(net, xm)) / (2 * h);
    worst = std::max(worst, (column - k.col(d)).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst / k.cwiseAbs().maxCoeff(), 1e-8);
  EXPECT_LT((k - k.transpose()).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(SpringMechanics, RestStiffnessIsTangentAtRestAndLinearInStiffness) {
  SpringNetwork net = grid_2d(4, 0.5);
  const Eigen::MatrixXd k_rest = Eigen::MatrixXd(rest_stiffness(net));
  const Eigen::MatrixXd k_tangent = Eigen::MatrixXd(tangent_stiffness(net, flat_positions(net)));
  EXPECT_LT((k_rest - k_tangent).cwiseAbs().maxCoeff(), 1e-12);
  // K(k) = sum_s k_s g_s g_s^T: doubling every stiffness doubles K; a rigid translation is free.
  for (auto& s : net.springs) s.stiffness *= 2.0;
  EXPECT_LT((Eigen::MatrixXd(rest_stiffness(net)) - 2.0 * k_rest).cwiseAbs().maxCoeff(), 1e-12);
  Eigen::VectorXd translation(net.positions.size() * 2);
  for (size_t q = 0; q < net.positions.size(); ++q) translation.segment<2>(2 * q) << 1.0, -0.5;
  EXPECT_LT((k_rest * translation).norm(), 1e-12);
}

TEST(SpringMechanics, NewtonApproachesLinearSolutionForSmallLoads) {
  const SpringNetwork net = grid_2d(4, 0.5);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(static_cast<int>(net.positions.size()) * 2);
  for (int j = 0; j < 4; ++j) f.segment<2>(2 * (j * 4 + 3)) << 0.3, -0.2;
  // The nonlinear part of the response is second order in the load: the relative difference
  // between Newton and linear halves when the load halves.
  double previous = 0.0;
  for (double scale : {1e-2, 5e-3, 2.5e-3}) {
    const auto linear = solve_spring_linear(net, scale * f);
    const auto newton = solve_spring_newton(net, scale * f);
    ASSERT_TRUE(newton.converged);
    EXPECT_LT(newton.relative_residual, 1e-10);
    const double difference =
        (newton.displacement - linear.displacement).norm() / linear.displacement.norm();
    if (previous > 0.0) {
      EXPECT_NEAR(previous / difference, 2.0, 0.05);
    }
    previous = difference;
  }
  EXPECT_LT(previous, 1e-3);
}

TEST(SpringMechanics, NewtonConvergesUnderLargeLoadWithSteps) {
  // Tip deflection about 25% of the grid size: clearly nonlinear (2% off the linear answer).
  const SpringNetwork net = grid_2d(4, 0.5);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(static_cast<int>(net.positions.size()) * 2);
  for (int j = 0; j < 4; ++j) f.segment<2>(2 * (j * 4 + 3)) << 0.0, -0.3;
  SpringSolveOptions options;
  options.load_steps = 3;
  const auto newton = solve_spring_newton(net, f, options);
  ASSERT_TRUE(newton.converged);
  // Equilibrium of the exact forces at the solution.
  const Eigen::VectorXd residual =
      f + spring_forces(net, flat_positions(net) + newton.displacement);
  for (int q = 0; q < 16; ++q) {
    if (q % 4 != 0) {
      EXPECT_LT(residual.segment<2>(2 * q).norm(), 1e-9 * f.norm());
    }
  }
}

TEST(SpringMechanics, DampingAlphaFollowsS15) {
  SpringNetwork net = chain({400.0}, 0.5);
  net.masses = {2.0, 3.0};
  assign_damping_alpha(net, 200.0);
  EXPECT_NEAR(net.springs[0].damping, (1.0 / 200.0) * 2.0 * std::sqrt(400.0 * 5.0) / 0.5, 1e-14);
  assign_damping_ratio(net, 0.1);  // particle 0 is held: the oscillator is particle 1 alone
  EXPECT_NEAR(net.springs[0].damping, 0.2 * std::sqrt(400.0 * 3.0), 1e-13);
  net.fixed[0] = false;  // both free: the reduced mass 2 * 3 / 5
  assign_damping_ratio(net, 0.1);
  EXPECT_NEAR(net.springs[0].damping, 0.2 * std::sqrt(400.0 * 6.0 / 5.0), 1e-14);
}

}  // namespace
}  // namespace isospring::analysis
