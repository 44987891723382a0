// The fused force pass and the allocation-free Verlet step against the straightforward
// implementation they replace (separate spring and damping passes, fresh vectors): the same
// operations in the same order, so the results must be identical to the last bit.
#include <gtest/gtest.h>

#include <random>

#include "isospring/analysis/spring_dynamics.hpp"
#include "isospring/analysis/spring_mechanics.hpp"
#include "random_lattice.hpp"

namespace isospring::analysis {
namespace {

// The former step_velocity_verlet, verbatim in its arithmetic.
void reference_verlet(const SpringNetwork& net, SpringState& state, const Eigen::VectorXd& f,
                      double dt) {
  Eigen::VectorXd inverse_mass = mass_diagonal(net).cwiseInverse();
  for (int dof : fixed_dofs(net)) inverse_mass[dof] = 0.0;
  auto acceleration = [&](const Eigen::VectorXd& x, const Eigen::VectorXd& v) {
    return Eigen::VectorXd(
        (spring_forces(net, x) + damping_forces(net, x, v) + f).cwiseProduct(inverse_mass));
  };
  const Eigen::VectorXd half = state.v + 0.5 * dt * acceleration(state.x, state.v);
  state.x += dt * half;
  state.v = half + 0.5 * dt * acceleration(state.x, half);
}

// A moving, deformed state: rest positions plus a random displacement and velocity.
SpringState random_state(const SpringNetwork& net, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.05, 0.05);
  SpringState state = rest_state(net);
  for (Eigen::Index d = 0; d < state.x.size(); ++d) {
    state.x[d] += u(rng);
    state.v[d] = 10.0 * u(rng);
  }
  return state;
}

TEST(SpringForcePass, FusedForcesAreBitForBitTheSeparateOnes) {
  for (int dim : {2, 3}) {
    const SpringNetwork net = random_lattice(5, dim, 1);
    const SpringState state = random_state(net, 2);
    Eigen::VectorXd f_spring, f_damping;
    spring_and_damping_forces(net, state.x, state.v, f_spring, f_damping);
    const Eigen::VectorXd spring = spring_forces(net, state.x);
    const Eigen::VectorXd damping = damping_forces(net, state.x, state.v);
    ASSERT_GT(spring.norm(), 0.0);
    ASSERT_GT(damping.norm(), 0.0);
    EXPECT_EQ((f_spring - spring).cwiseAbs().maxCoeff(), 0.0) << "dimension " << dim;
    EXPECT_EQ((f_damping - damping).cwiseAbs().maxCoeff(), 0.0) << "dimension " << dim;
  }
}

TEST(SpringForcePass, VerletStepIsBitForBitTheReference) {
  for (int dim : {2, 3}) {
    const SpringNetwork net = random_lattice(5, dim, 3);
    SpringState state = random_state(net, 4), reference = state;
    const Eigen::VectorXd f = Eigen::VectorXd::Constant(state.x.size(), 0.3);
    for (int step = 0; step < 50; ++step) {
      step_velocity_verlet(net, state, f, 1e-3);
      reference_verlet(net, reference, f, 1e-3);
    }
    EXPECT_GT((state.x - rest_state(net).x).norm(), 0.0);
    EXPECT_EQ((state.x - reference.x).cwiseAbs().maxCoeff(), 0.0) << "dimension " << dim;
    EXPECT_EQ((state.v - reference.v).cwiseAbs().maxCoeff(), 0.0) << "dimension " << dim;
  }
  // A network of another size on the same thread: the per-thread work vectors are resized.
  const SpringNetwork small = random_lattice(3, 3, 5);
  SpringState state = random_state(small, 6), reference = state;
  const Eigen::VectorXd f = Eigen::VectorXd::Zero(state.x.size());
  step_velocity_verlet(small, state, f, 1e-3);
  reference_verlet(small, reference, f, 1e-3);
  EXPECT_EQ((state.v - reference.v).cwiseAbs().maxCoeff(), 0.0);
}

}  // namespace
}  // namespace isospring::analysis
