// The reduced spring model (spring_reduced_model.hpp) against independent computations: its
// Ritz values against a dense generalized eigensolver, its static response against the full
// sparse solve, its motion against the full-space integrator, and its errors on bad input.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>

#include "isospring/analysis/spring_mechanics.hpp"
#include "isospring/analysis/spring_reduced_model.hpp"
#include "isospring/analysis/spring_static.hpp"
#include "isospring/nurbs/error.hpp"
#include "random_lattice.hpp"

namespace isospring::analysis {
namespace {

// Dense K and M on the free DOFs.
struct DenseSystem {
  Eigen::MatrixXd k, m;
};
DenseSystem dense_system(const SpringNetwork& net) {
  const FreeDofSet dofs(static_cast<int>(net.positions.size()) * net.dimension, fixed_dofs(net));
  return {Eigen::MatrixXd(dofs.restrict(rest_stiffness(net))),
          Eigen::MatrixXd(dofs.restrict(mass_diagonal(net)).asDiagonal())};
}

// A tip load: every particle of the face x = max pushed along (0.3, -1, 0.5).
Eigen::VectorXd tip_load(const SpringNetwork& net, double size) {
  Eigen::VectorXd f =
      Eigen::VectorXd::Zero(static_cast<Eigen::Index>(net.positions.size()) * net.dimension);
  double x_max = -1e300;
  for (const auto& p : net.positions) x_max = std::max(x_max, p.x());
  for (size_t q = 0; q < net.positions.size(); ++q)
    if (net.positions[q].x() > x_max - 0.5)
      for (int c = 0; c < net.dimension; ++c)
        f[static_cast<Eigen::Index>(q) * net.dimension + c] =
            size * Eigen::Vector3d(0.3, -1.0, 0.5)[c];
  return f;
}

TEST(ReducedSpringModel, ModesAreTheLowestEigenpairsOfTheDenseProblem) {
  for (int dim : {2, 3}) {
    const SpringNetwork net = random_lattice(dim == 3 ? 4 : 6, dim, 11);
    ReducedModelOptions options;
    options.modes = 8;
    const ReducedSpringModel model(net, 1e-3, options);
    const DenseSystem dense = dense_system(net);
    const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> reference(dense.k, dense.m);
    ASSERT_EQ(model.size(), 8);
    for (int j = 0; j < 8; ++j)  // Lanczos to 1e-12 against dense tridiagonal QR
      EXPECT_NEAR(model.eigenvalues()[j], reference.eigenvalues()[j],
                  1e-9 * reference.eigenvalues()[j])
          << "dim " << dim << ", mode " << j;
    // M-orthonormal on the network's DOFs, zero on the fixed ones.
    const Eigen::MatrixXd gram =
        model.basis().transpose() * mass_diagonal(net).asDiagonal() * model.basis();
    EXPECT_LT((gram - Eigen::MatrixXd::Identity(8, 8)).cwiseAbs().maxCoeff(), 1e-12);
    for (int dof : fixed_dofs(net)) EXPECT_EQ(model.basis().row(dof).norm(), 0.0);
  }
}

TEST(ReducedSpringModel, LoadShapesMakeTheirStaticResponseExact) {
  const SpringNetwork net = random_lattice(5, 3, 7);
  const Eigen::VectorXd load = tip_load(net, 1.0);
  const Eigen::VectorXd full = solve_spring_linear(net, load).displacement;
  ReducedModelOptions options;
  options.modes = 6;
  options.load_shapes = {load};
  const ReducedSpringModel with_shape(net, 1e-3, options);
  // Exact up to the orthonormalisation's round-off (condition of K ~ 1e3 here).
  EXPECT_LT((with_shape.static_displacement(load) - full).norm(), 1e-10 * full.norm());
  // Modes alone converge towards it as the basis grows (nested Ritz spaces: the error in the
  // energy norm cannot grow).
  const Eigen::MatrixXd k = Eigen::MatrixXd(rest_stiffness(net));
  double previous = 1e300;
  for (int modes : {2, 6, 18, 54}) {
    const ReducedSpringModel model(net, 1e-3, {modes, {}});
    const Eigen::VectorXd e = model.static_displacement(load) - full;
    const double energy_error = std::sqrt(e.dot(k * e) / full.dot(k * full));
    std::printf("%d modes: static energy-norm error %.3g\n", modes, energy_error);
    EXPECT_LE(energy_error, previous * (1.0 + 1e-9));
    previous = energy_error;
  }
  EXPECT_LT(previous, 0.2);
  EXPECT_GT(previous, 1e-6);  // still a truncation, unlike the load shape
}

TEST(ReducedSpringModel, FullBasisMovesAsTheFullIntegratorNearRest) {
  // Every free DOF in the basis: the projection is the identity, so the reduced step is the
  // full linearly implicit step with linear spring forces. Under a load of strain ~1e-8 the full
  // integrator's nonlinear forces differ from linear ones by ~1e-8 relative.
  const SpringNetwork net = random_lattice(3, 3, 5);
  const int free = static_cast<int>(net.positions.size() * 3 - fixed_dofs(net).size());
  ReducedModelOptions options;
  options.modes = free - 1;
  options.load_shapes = {tip_load(net, 1e-5)};
  ReducedSpringModel model(net, 2e-3, options);
  ASSERT_EQ(model.size(), free);
  const ReductionError error = reduction_error(net, model, tip_load(net, 1e-5), 200);
  EXPECT_LT(error.static_relative, 1e-10);
  EXPECT_LT(error.dynamic_relative, 1e-6) << error.dynamic_relative;
  // Against the linearised full network the step is the same arithmetic in another basis. (At
  // the small load above the full model's displacement x - X itself carries a relative
  // round-off of eps |X| / |u| ~ 1e-8, so this is checked at a load 1e5 x larger: linear.)
  const ReductionError linear = reduction_error(net, model, tip_load(net, 1.0), 200);
  EXPECT_LT(linear.projection_relative, 1e-11) << linear.projection_relative;
  EXPECT_FALSE(error.exact_diverged);
}

TEST(ReducedSpringModel, FewModesPlusTheLoadShapeTrackTheFullMotion) {
  // The use case: 12 modes and the load's static shape, 13 of the network's 300 free DOFs; a
  // step load held for 2000 steps of 1 ms (2.5 periods of the lowest mode, 0.79 s). The error is
  // the higher modes' share of the motion.
  const SpringNetwork net = random_lattice(5, 3, 9);
  const Eigen::VectorXd load = tip_load(net, 1.0);
  ReducedSpringModel model(net, 1e-3, {12, {load}});
  const ReductionError with_shape = reduction_error(net, model, load, 2000);
  ReducedSpringModel modes_only(net, 1e-3, {12, {}});
  const ReductionError without = reduction_error(net, modes_only, load, 2000);
  std::printf("lowest period %.3g s\n", 2.0 * M_PI / std::sqrt(model.eigenvalues()[0]));
  std::printf(
      "12 modes + load shape: static %.3g, projection %.3g, dynamic %.3g; 12 modes: static %.3g, "
      "projection %.3g, dynamic %.3g\n",
      with_shape.static_relative, with_shape.projection_relative, with_shape.dynamic_relative,
      without.static_relative, without.projection_relative, without.dynamic_relative);
  EXPECT_LT(with_shape.static_relative, 1e-10);
  EXPECT_LT(with_shape.projection_relative, 0.05);
  EXPECT_LT(with_shape.dynamic_relative, 0.05);
  EXPECT_LT(with_shape.dynamic_relative, without.dynamic_relative);
  // The particle read-out and the force projection agree with the full field.
  model.reset();
  for (int s = 0; s < 10; ++s) model.step(model.reduce_force(load));
  const Eigen::VectorXd u = model.displacement();
  for (int p : {7, 60, 124})
    EXPECT_LT((model.particle_displacement(p) - u.segment(3 * p, 3)).norm(), 1e-14 * u.norm());
  Eigen::VectorXd point = Eigen::VectorXd::Zero(u.size());
  point.segment(3 * 60, 3) = Eigen::Vector3d(1, 2, 3);
  EXPECT_LT((model.reduce_particle_force(60, {1, 2, 3}) - model.reduce_force(point)).norm(), 1e-12);
}

TEST(ReducedSpringModel, BadInputIsNamed) {
  const SpringNetwork net = random_lattice(3, 3, 5);
  auto message = [&](double dt, const ReducedModelOptions& options) {
    try {
      ReducedSpringModel model(net, dt, options);
    } catch (const nurbs::InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(0.0, {4, {}}).find("time step"), std::string::npos);
  EXPECT_NE(message(1e-3, {1000, {}}).find("modes = 1000"), std::string::npos);
  EXPECT_NE(message(1e-3, {0, {}}).find("no basis vectors"), std::string::npos);
  EXPECT_NE(message(1e-3, {2, {Eigen::VectorXd::Ones(5)}}).find("has 5 entries"),
            std::string::npos);
  Eigen::VectorXd nan_load = tip_load(net, 1.0);
  nan_load[40] = std::nan("");
  EXPECT_NE(message(1e-3, {2, {nan_load}}).find("NaN"), std::string::npos);
  ReducedSpringModel model(net, 1e-3, {4, {}});
  EXPECT_THROW(model.particle_displacement(27), nurbs::InputError);
  EXPECT_THROW(model.reduce_force(Eigen::VectorXd::Ones(3)), nurbs::InputError);
  // A free-floating network: modes are fine (rigid modes come out ~0), load shapes are not.
  SpringNetwork floating = net;
  std::fill(floating.fixed.begin(), floating.fixed.end(), false);
  EXPECT_THROW(ReducedSpringModel(floating, 1e-3, {2, {tip_load(floating, 1.0)}}),
               std::runtime_error);
}

}  // namespace
}  // namespace isospring::analysis
