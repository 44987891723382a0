// Shear terms of spring networks (VolumeTerm::kind == CellEnergy::kShear, spring_volume.hpp):
// forces and tangent against finite differences of the energy, invariance under large rigid
// rotations, the patch test (a uniform strain of a distorted cell: exactly mu |V0| |dev eps|^2,
// and with a volume term lambda + 2 mu / d the isotropic energy), its rank, and the rest
// stiffness columns the fits use.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <random>

#include "isospring/analysis/spring_mechanics.hpp"
#include "isospring/analysis/spring_volume.hpp"

namespace isospring::analysis {
namespace {

// One distorted unit cell (corners jittered, so the trilinear map is not affine) with a shear
// term of modulus mu (and, when kappa > 0, a volume term too); no springs.
SpringNetwork shear_cell(int dim, double distortion, unsigned seed, double mu, double kappa) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-distortion, distortion);
  SpringNetwork net;
  net.dimension = dim;
  VolumeTerm term;
  for (int a = 0; a < volume_corners(dim); ++a) {
    Eigen::Vector3d x((a & 1) * 1.3, ((a >> 1) & 1) * 0.9, dim == 3 ? ((a >> 2) & 1) * 1.1 : 0.0);
    for (int c = 0; c < dim; ++c) x[c] += jitter(rng);
    net.positions.push_back(x);
    term.particles[static_cast<size_t>(a)] = a;
  }
  net.masses.assign(net.positions.size(), 1.0);
  net.fixed.assign(net.positions.size(), false);
  term.rest_volume = rest_cell_volume(net, term);
  term.kind = CellEnergy::kShear;
  term.modulus = mu;
  net.volumes.push_back(term);
  if (kappa > 0.0) {
    term.kind = CellEnergy::kVolume;
    term.modulus = kappa;
    net.volumes.push_back(term);
  }
  return net;
}

TEST(SpringShear, ForcesAndTangentMatchFiniteDifferencesOfTheEnergy) {
  for (int dim : {2, 3}) {
    const SpringNetwork net = shear_cell(dim, 0.2, 11 + static_cast<unsigned>(dim), 7.0, 0.0);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> move(-0.2, 0.2);
    Eigen::VectorXd x = flat_positions(net);
    for (Eigen::Index e = 0; e < x.size(); ++e) x[e] += move(rng);
    ASSERT_GT(spring_energy(net, x), 1e-3);
    const Eigen::VectorXd f = spring_forces(net, x);
    const Eigen::MatrixXd k = Eigen::MatrixXd(tangent_stiffness(net, x));
    const double h = 1e-6;
    for (Eigen::Index e = 0; e < x.size(); ++e) {
      Eigen::VectorXd plus = x, minus = x;
      plus[e] += h;
      minus[e] -= h;
      EXPECT_NEAR(f[e], -(spring_energy(net, plus) - spring_energy(net, minus)) / (2 * h), 1e-7);
      const Eigen::VectorXd df = (spring_forces(net, plus) - spring_forces(net, minus)) / (2 * h);
      EXPECT_NEAR((k.col(e) + df).norm(), 0.0, 1e-6) << "dim " << dim << " column " << e;
    }
    EXPECT_NEAR((k - k.transpose()).norm(), 0.0, 1e-12);
    // At rest: no force, and the tangent is mu sum_k g_k g_k^T of rest_stiffness_columns.
    const Eigen::VectorXd rest = flat_positions(net);
    EXPECT_LT(spring_forces(net, rest).norm(), 1e-12);
    const Eigen::MatrixXd k_rest = Eigen::MatrixXd(rest_stiffness(net));
    EXPECT_LT((Eigen::MatrixXd(tangent_stiffness(net, rest)) - k_rest).norm(), 1e-12);
    Eigen::MatrixXd from_columns = Eigen::MatrixXd::Zero(k_rest.rows(), k_rest.cols());
    const auto columns = rest_stiffness_columns(net, net.volumes[0]);
    EXPECT_EQ(columns.size(), dim == 3 ? 5u : 2u);
    for (const auto& g : columns) from_columns += 7.0 * g * g.transpose();
    EXPECT_LT((from_columns - k_rest).norm(), 1e-12 * k_rest.norm());
    // Rank: one per deviatoric strain mode of the mean strain.
    const Eigen::VectorXd eigenvalues =
        Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(k_rest).eigenvalues();
    const int modes = dim == 3 ? 5 : 2;
    EXPECT_LT(std::abs(eigenvalues[eigenvalues.size() - modes - 1]),
              1e-10 * eigenvalues.maxCoeff());
    EXPECT_GT(eigenvalues[eigenvalues.size() - modes], 1e-3 * eigenvalues.maxCoeff());
  }
}

TEST(SpringShear, LargeRigidRotationsCarryNoEnergyOrForce) {
  for (int dim : {2, 3}) {
    const SpringNetwork net = shear_cell(dim, 0.2, 31 + static_cast<unsigned>(dim), 7.0, 3.0);
    const Eigen::Matrix3d r =
        dim == 3 ? Eigen::AngleAxisd(1.1, Eigen::Vector3d(1.0, -2.0, 0.5).normalized())
                       .toRotationMatrix()
                 : Eigen::AngleAxisd(1.1, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    Eigen::VectorXd x(static_cast<Eigen::Index>(net.positions.size()) * dim);
    for (size_t a = 0; a < net.positions.size(); ++a)
      x.segment(static_cast<Eigen::Index>(a) * dim, dim) =
          (r * net.positions[a] + Eigen::Vector3d(0.3, -0.2, 0.7)).head(dim);
    EXPECT_LT(spring_energy(net, x), 1e-12);
    EXPECT_LT(spring_forces(net, x).norm(), 1e-11);
    // A stretch is not free.
    Eigen::VectorXd stretched = x;
    for (Eigen::Index e = 0; e < x.size(); e += dim) stretched[e] *= 1.1;
    EXPECT_GT(spring_energy(net, stretched), 1e-3);
  }
}

// Patch test: under a uniform strain u = H X a distorted cell's shear term stores exactly
// mu |V0| |dev eps|^2 (its mean deformation gradient is exact for affine motions), and shear
// plus volume terms with kappa = lambda + 2 mu / d store the isotropic energy
// |V0| (mu eps:eps + lambda / 2 (tr eps)^2), whatever the cell's shape.
TEST(SpringShear, PatchTestUniformStrainIsReproducedExactly) {
  const double mu = 5.0, lambda = 9.0;
  for (int dim : {2, 3}) {
    const double kappa = lambda + 2.0 * mu / dim;
    for (bool with_volume : {false, true}) {
      const SpringNetwork net =
          shear_cell(dim, 0.25, 41 + static_cast<unsigned>(dim), mu, with_volume ? kappa : 0.0);
      const double v0 = std::abs(net.volumes[0].rest_volume);
      const Eigen::MatrixXd k = Eigen::MatrixXd(rest_stiffness(net));
      std::mt19937 rng(17);
      std::uniform_real_distribution<double> entry(-1.0, 1.0);
      for (int trial = 0; trial < 5; ++trial) {
        Eigen::MatrixXd grad(dim, dim);
        for (int r = 0; r < dim; ++r)
          for (int c = 0; c < dim; ++c) grad(r, c) = entry(rng);
        Eigen::VectorXd u(k.rows());
        for (size_t a = 0; a < net.positions.size(); ++a)
          u.segment(static_cast<Eigen::Index>(a) * dim, dim) = grad * net.positions[a].head(dim);
        const Eigen::MatrixXd eps = 0.5 * (grad + grad.transpose());
        const Eigen::MatrixXd dev = eps - eps.trace() / dim * Eigen::MatrixXd::Identity(dim, dim);
        const double expected =
            with_volume ? v0 * (mu * eps.squaredNorm() + 0.5 * lambda * eps.trace() * eps.trace())
                        : v0 * mu * dev.squaredNorm();
        EXPECT_NEAR(0.5 * u.dot(k * u), expected, 1e-12 * v0 * (mu + lambda))
            << "dim " << dim << (with_volume ? " with volume term" : "");
      }
    }
  }
}

}  // namespace
}  // namespace isospring::analysis
