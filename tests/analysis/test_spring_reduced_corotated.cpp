// The corotated reduced model (spring_reduced_corotated.hpp, spring_corotation.hpp): exact
// identities (polar factor, zero force under rigid motion, the linear force with identity
// rotations), the small-deformation limit of the linear reduced model, and the large-rotation
// error against the full nonlinear network.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <cmath>
#include <iostream>
#include <random>

#include "beam_lattice.hpp"
#include "isospring/analysis/spring_corotation.hpp"
#include "isospring/analysis/spring_mechanics.hpp"
#include "isospring/analysis/spring_reduced_corotated.hpp"
#include "isospring/analysis/spring_static.hpp"
#include "random_lattice.hpp"

namespace isospring::analysis {
namespace {

Eigen::Matrix3d random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> normal;
  return Eigen::Quaterniond(normal(rng), normal(rng), normal(rng), normal(rng))
      .normalized()
      .toRotationMatrix();
}

TEST(CorotatedForces, PolarRotationIsTheRotationOfQTimesSymmetric) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Matrix3d q = random_rotation(rng);
    Eigen::Matrix3d b;
    for (int e = 0; e < 9; ++e) b(e) = uniform(rng);
    // S symmetric positive definite, condition up to ~1e3 (a slender neighbourhood).
    const Eigen::Matrix3d s = b * b.transpose() + 1e-2 * Eigen::Matrix3d::Identity();
    EXPECT_LT((polar_rotation(q * s) - q).norm(), 1e-13) << trial;
  }
  // Flat A (coplanar neighbours, rank 2): the SVD branch still returns Q.
  const Eigen::Matrix3d q = random_rotation(rng);
  const Eigen::Matrix3d flat = Eigen::Vector3d(2.0, 1.0, 0.0).asDiagonal();
  EXPECT_LT((polar_rotation(q * flat) - q).norm(), 1e-13);
}

// Positions and velocities of the network moved rigidly: x = Q X + t, v = w x (x - c).
void rigid_motion(const SpringNetwork& net, const Eigen::Matrix3d& q, Eigen::VectorXd& x,
                  Eigen::VectorXd& v) {
  const int d = net.dimension;
  const Eigen::Vector3d t(0.7, -1.3, d == 3 ? 2.1 : 0.0), w(d == 3 ? 0.4 : 0.0,
                                                             d == 3 ? -0.9 : 0.0, 1.7);
  x.resize(static_cast<Eigen::Index>(net.positions.size()) * d);
  v.resizeLike(x);
  for (size_t p = 0; p < net.positions.size(); ++p) {
    const Eigen::Vector3d moved = q * net.positions[p] + t;
    x.segment(static_cast<Eigen::Index>(p) * d, d) = moved.head(d);
    v.segment(static_cast<Eigen::Index>(p) * d, d) = w.cross(moved - t).head(d);
  }
}

TEST(CorotatedForces, RigidMotionOfTheRestStateHasZeroForceTheLinearOneNot) {
  std::mt19937 rng(5);
  for (int dim : {3, 2}) {
    const SpringNetwork net = random_lattice(dim == 3 ? 4 : 6, dim, 13);
    const CorotatedForces corotated(net);
    const Eigen::SparseMatrix<double> k = rest_stiffness(net), c = rest_damping(net);
    for (double angle : {0.3, 1.2, 3.0}) {
      const Eigen::Matrix3d q =
          dim == 3 ? Eigen::Matrix3d(Eigen::AngleAxisd(angle, Eigen::Vector3d(1, 2, -0.5).normalized()))
                   : Eigen::Matrix3d(Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()));
      Eigen::VectorXd x, v, f;
      rigid_motion(net, q, x, v);
      const Eigen::VectorXd linear = -(k * (x - flat_positions(net))) - c * v;
      corotated.forces(x, v, f);
      // Relative to the linear model's spurious force, which is O(k L angle).
      EXPECT_LT(f.norm(), 1e-12 * linear.norm()) << dim << "D, angle " << angle;
      EXPECT_GT(linear.norm(), 1e2 * angle) << dim << "D";
    }
  }
  (void)rng;
}

TEST(CorotatedForces, IdentityRotationsGiveTheLinearForce) {
  for (int dim : {3, 2}) {
    const SpringNetwork net = random_lattice(4, dim, 17);
    const CorotatedForces corotated(net);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> uniform(-0.2, 0.2);
    const Eigen::VectorXd rest = flat_positions(net);
    Eigen::VectorXd x = rest, v(rest.size());
    for (Eigen::Index e = 0; e < x.size(); ++e) {
      x[e] += uniform(rng);
      v[e] = uniform(rng);
    }
    const std::vector<Eigen::Matrix3d> identity(net.positions.size(), Eigen::Matrix3d::Identity());
    Eigen::VectorXd f;
    corotated.rotated_forces(identity, x, v, true, f);
    const Eigen::VectorXd linear = -(rest_stiffness(net) * (x - rest)) - rest_damping(net) * v;
    EXPECT_LT((f - linear).norm(), 1e-13 * linear.norm()) << dim << "D";
  }
}

TEST(CorotatedReduced, Explore) {
  const SpringNetwork net = beam_lattice(10, 3, 3, 1e3, 1e-3);
  const double dt = std::getenv("DT") ? std::atof(std::getenv("DT")) : 1e-3;
  CorotatedReducedModel model(net, dt, {{24, {beam_tip_load(net, 1.0, 0.0)}}, 6});
  std::cout << "r " << model.size() << " max lambda " << model.linear().eigenvalues().maxCoeff() << "\n";
  for (double bend : {4.0, 32.0}) {
    const LargeRotationError e = large_rotation_error(net, model, beam_tip_load(net, bend, 0.0), static_cast<int>(0.3 / dt));
    std::cout << "bend " << bend << " rot " << e.rotation_degrees << " static lin "
              << e.static_linear << " corot " << e.static_corotated << " best " << e.static_best
              << " dyn lin " << e.dynamic_linear << " corot " << e.dynamic_corotated << " omax "
              << e.static_o_max << "\n";
  }
}

}  // namespace
}  // namespace isospring::analysis
namespace isospring::analysis {
TEST(CorotatedDebug, ForceAtLinearSolution) {
  const SpringNetwork net = beam_lattice(10, 3, 3, 1e3, 1e-3);
  const CorotatedForces corotated(net);
  for (double bend : {0.05, 0.5, 5.0}) {
    const Eigen::VectorXd f = beam_tip_load(net, bend, 0.0);
    const Eigen::VectorXd u = solve_spring_linear(net, f).displacement;
    Eigen::VectorXd fc;
    corotated.forces(flat_positions(net) + u, Eigen::VectorXd(), fc);
    const Eigen::VectorXd fl = -(rest_stiffness(net) * u);
    const FreeDofSet dofs(static_cast<int>(u.size()), fixed_dofs(net));
    std::cout << bend << " rel diff " << dofs.restrict(Eigen::VectorXd(fc - fl)).norm() / dofs.restrict(fl).norm() << " umax " << u.cwiseAbs().maxCoeff() << "\n";
    std::vector<Eigen::Matrix3d> r;
    corotated.rotations(flat_positions(net) + u, r);
    for (int p : {1, 5, 9, 14, 40, 89}) {
      Eigen::AngleAxisd aa(r[p]);
      std::cout << "  p" << p << " angle " << aa.angle() << " axis " << aa.axis().transpose() << "\n";
    }
  }
}
}
