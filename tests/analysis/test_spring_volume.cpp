// Volume terms of spring networks (spring_volume.hpp): exact volumes, gradient and Hessian against
// finite differences, forces and tangent against finite differences of the energy, the rigid-body
// null space, and the [W05] cubic-lattice moduli with and without the volume term (nmsm.md).
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <random>

#include "isospring/analysis/spring_dynamics.hpp"
#include "isospring/analysis/spring_mechanics.hpp"
#include "isospring/analysis/spring_volume.hpp"

namespace isospring::analysis {
namespace {

// One cell: corners of a (distorted) unit square/cube in tensor order, no springs.
SpringNetwork one_cell(int dim, double distortion, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-distortion, distortion);
  SpringNetwork net;
  net.dimension = dim;
  VolumeTerm term;
  for (int a = 0; a < volume_corners(dim); ++a) {
    Eigen::Vector3d x((a & 1) * 1.0, ((a >> 1) & 1) * 1.0, dim == 3 ? ((a >> 2) & 1) * 1.0 : 0.0);
    for (int c = 0; c < dim; ++c) x[c] += jitter(rng);
    net.positions.push_back(x);
    term.particles[static_cast<size_t>(a)] = a;
  }
  net.masses.assign(net.positions.size(), 1.0);
  net.fixed.assign(net.positions.size(), false);
  term.rest_volume = rest_cell_volume(net, term);
  term.modulus = 7.0;
  net.volumes.push_back(term);
  return net;
}

TEST(SpringVolume, ExactVolumes) {
  // A parallelepiped spanned by a, b, c has volume det[a b c] (trilinear = affine map here).
  SpringNetwork net = one_cell(3, 0.0, 1);
  const Eigen::Matrix3d span =
      (Eigen::Matrix3d() << 2.0, 0.3, 0.1, 0.2, 1.5, -0.4, 0.0, 0.5, 0.8).finished();
  for (int a = 0; a < 8; ++a)
    net.positions[static_cast<size_t>(a)] =
        span * Eigen::Vector3d((a & 1) * 1.0, ((a >> 1) & 1) * 1.0, ((a >> 2) & 1) * 1.0);
  EXPECT_NEAR(rest_cell_volume(net, net.volumes[0]), span.determinant(), 1e-13);
  // A quadrilateral's area is the shoelace formula (corners 0 1 3 2 around it).
  SpringNetwork quad = one_cell(2, 0.3, 2);
  const auto& p = quad.positions;
  const int ring[4] = {0, 1, 3, 2};
  double shoelace = 0.0;
  for (int e = 0; e < 4; ++e) {
    const Eigen::Vector3d& u = p[static_cast<size_t>(ring[e])];
    const Eigen::Vector3d& v = p[static_cast<size_t>(ring[(e + 1) % 4])];
    shoelace += 0.5 * (u.x() * v.y() - v.x() * u.y());
  }
  EXPECT_NEAR(rest_cell_volume(quad, quad.volumes[0]), shoelace, 1e-14);
}

TEST(SpringVolume, GradientAndHessianMatchFiniteDifferences) {
  for (int dim : {2, 3}) {
    const SpringNetwork net = one_cell(dim, 0.25, 3 + static_cast<unsigned>(dim));
    const VolumeTerm& term = net.volumes[0];
    const Eigen::VectorXd x = flat_positions(net);
    Eigen::VectorXd gradient;
    Eigen::MatrixXd hessian;
    cell_volume(term, x, dim, &gradient, &hessian);
    const double h = 1e-6;
    for (Eigen::Index e = 0; e < x.size(); ++e) {
      Eigen::VectorXd plus = x, minus = x;
      plus[e] += h;
      minus[e] -= h;
      Eigen::VectorXd g_plus, g_minus;
      const double v_plus = cell_volume(term, plus, dim, &g_plus);
      const double v_minus = cell_volume(term, minus, dim, &g_minus);
      EXPECT_NEAR(gradient[e], (v_plus - v_minus) / (2 * h), 1e-8) << "dim " << dim;
      EXPECT_NEAR((hessian.col(e) - (g_plus - g_minus) / (2 * h)).norm(), 0.0, 1e-7)
          << "dim " << dim << " column " << e;
    }
    EXPECT_NEAR((hessian - hessian.transpose()).norm(), 0.0, 1e-14);
  }
}

TEST(SpringVolume, ForcesAndTangentMatchFiniteDifferencesOfTheEnergy) {
  for (int dim : {2, 3}) {
    const SpringNetwork net = one_cell(dim, 0.2, 11 + static_cast<unsigned>(dim));
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> move(-0.15, 0.15);
    Eigen::VectorXd x = flat_positions(net);
    for (Eigen::Index e = 0; e < x.size(); ++e) x[e] += move(rng);  // deformed: V != V0
    ASSERT_GT(std::abs(volume_energy(net, x)), 1e-4);
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
    // At rest: no force, and the tangent is the rank-one kappa/|V0| b b^T of rest_stiffness.
    const Eigen::VectorXd rest = flat_positions(net);
    EXPECT_LT(spring_forces(net, rest).norm(), 1e-12);
    EXPECT_LT((Eigen::MatrixXd(tangent_stiffness(net, rest)) - Eigen::MatrixXd(rest_stiffness(net)))
                  .norm(),
              1e-12);
  }
}

TEST(SpringVolume, RigidMotionsAreInTheNullSpace) {
  // Springs plus volume terms, nothing fixed: exactly d(d+1)/2 zero eigenvalues, and the
  // translations and infinitesimal rotations are among them.
  for (int dim : {2, 3}) {
    SpringNetwork net = one_cell(dim, 0.2, 21 + static_cast<unsigned>(dim));
    const int corners = volume_corners(dim);
    for (int a = 0; a < corners; ++a)
      for (int b = a + 1; b < corners; ++b) {
        Spring s;
        s.i = a;
        s.j = b;
        s.stiffness = 1.0 + 0.1 * (a + b);
        s.rest_length =
            (net.positions[static_cast<size_t>(a)] - net.positions[static_cast<size_t>(b)]).norm();
        net.springs.push_back(s);
      }
    const Eigen::MatrixXd k = Eigen::MatrixXd(rest_stiffness(net));
    const Eigen::VectorXd x = flat_positions(net);
    for (int axis = 0; axis < 3; ++axis) {
      Eigen::VectorXd translation = Eigen::VectorXd::Zero(x.size());
      Eigen::VectorXd rotation = Eigen::VectorXd::Zero(x.size());
      const Eigen::Vector3d w = Eigen::Vector3d::Unit(axis);
      for (int a = 0; a < corners; ++a) {
        const Eigen::Vector3d p = net.positions[static_cast<size_t>(a)];
        const Eigen::Vector3d r = w.cross(p);
        for (int c = 0; c < dim; ++c) {
          if (c == axis) translation[a * dim + c] = 1.0;
          rotation[a * dim + c] = r[c];
        }
      }
      if (axis < dim) {
        EXPECT_LT((k * translation).norm(), 1e-12);
      }
      if (dim == 3 || axis == 2) {
        EXPECT_LT((k * rotation).norm(), 1e-12) << "axis " << axis;
      }
    }
    const Eigen::VectorXd eigenvalues =
        Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(k).eigenvalues();
    const int rigid = dim * (dim + 1) / 2;
    EXPECT_LT(std::abs(eigenvalues[rigid - 1]), 1e-10 * eigenvalues.maxCoeff());
    EXPECT_GT(eigenvalues[rigid], 1e-6 * eigenvalues.maxCoeff());
    // The volume term alone would be rank one; it adds stiffness to the springs' K.
    SpringNetwork springs_only = net;
    springs_only.volumes.clear();
    EXPECT_GT((k - Eigen::MatrixXd(rest_stiffness(springs_only))).norm(), 1.0);
  }
}

// [W05]'s cubic lattice (nmsm.md): edge springs k1, face diagonals k2, body diagonals k3, edge h.
// One cell of the periodic lattice carries k1/4 per edge (shared by 4 cells), k2/2 per face
// diagonal (2 cells), k3 per body diagonal; the volume term adds kappa to C11 and C12. The energy
// of an affine displacement u = H x is h^3/2 eps:C:eps with the cubic C11, C12, C44.
TEST(SpringVolume, CubicLatticeModuliAndPoissonRatio) {
  const double h = 0.5, k3 = 3.0, k2 = 5.0;
  const double k1 = (3.0 * k2 + 8.0 * k3) / 3.0;  // isotropy 3k1 - 3k2 - 8k3 = 0
  for (bool with_volume : {false, true}) {
    SpringNetwork net = one_cell(3, 0.0, 1);
    for (auto& p : net.positions) p *= h;
    net.volumes[0].rest_volume = h * h * h;
    const double c44_springs = (k2 + 4.0 * k3 / 3.0) / h;
    net.volumes[0].modulus = with_volume ? c44_springs : 0.0;  // kappa = C44
    for (int a = 0; a < 8; ++a)
      for (int b = a + 1; b < 8; ++b) {
        const int differing = __builtin_popcount(static_cast<unsigned>(a ^ b));
        Spring s;
        s.i = a;
        s.j = b;
        s.stiffness = differing == 1 ? k1 / 4.0 : differing == 2 ? k2 / 2.0 : k3;
        s.rest_length =
            (net.positions[static_cast<size_t>(a)] - net.positions[static_cast<size_t>(b)]).norm();
        net.springs.push_back(s);
      }
    const double kappa = net.volumes[0].modulus;
    const double c11 = (k1 + 2.0 * k2 + 4.0 * k3 / 3.0) / h + kappa;
    const double c12 = c44_springs + kappa;
    const double c44 = c44_springs;
    const Eigen::MatrixXd k = Eigen::MatrixXd(rest_stiffness(net));
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> entry(-1.0, 1.0);
    for (int trial = 0; trial < 5; ++trial) {
      Eigen::Matrix3d grad;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) grad(r, c) = entry(rng);
      Eigen::VectorXd u(24);
      for (int a = 0; a < 8; ++a)
        u.segment<3>(3 * a) = grad * net.positions[static_cast<size_t>(a)];
      const Eigen::Matrix3d eps = 0.5 * (grad + grad.transpose());
      double energy = 0.0;  // 1/2 eps:C:eps per unit volume, cubic symmetry
      for (int i = 0; i < 3; ++i) {
        energy += 0.5 * c11 * eps(i, i) * eps(i, i);
        for (int j = 0; j < 3; ++j)
          if (i != j) energy += 0.5 * c12 * eps(i, i) * eps(j, j) + c44 * eps(i, j) * eps(i, j);
      }
      EXPECT_NEAR(0.5 * u.dot(k * u), h * h * h * energy, 1e-10 * h * h * h * c11);
    }
    // Isotropic (C11 - C12 = 2 C44) both ways; nu = lambda / (2 (lambda + mu)), lambda = C12.
    EXPECT_NEAR(c11 - c12, 2.0 * c44, 1e-12 * c11);
    EXPECT_NEAR(c12 / (2.0 * (c12 + c44)), with_volume ? 1.0 / 3.0 : 0.25, 1e-12);
  }
}

// The dynamics run volume terms: an undamped cell with edge springs and a stiff volume term,
// squeezed and released, keeps its total energy under velocity Verlet (symplectic) and only
// loses it under backward Euler (dissipative); both oscillate about the rest volume.
TEST(SpringVolume, DynamicsConserveOrDissipateTheVolumeEnergy) {
  SpringNetwork net = one_cell(3, 0.0, 1);
  for (int a = 0; a < 8; ++a)
    for (int b = a + 1; b < 8; ++b)
      if (__builtin_popcount(static_cast<unsigned>(a ^ b)) == 1) {
        Spring s;
        s.i = a;
        s.j = b;
        s.stiffness = 10.0;
        s.rest_length = 1.0;
        net.springs.push_back(s);
      }
  net.volumes[0].modulus = 200.0;  // the volume term dominates the squeeze
  for (int a = 0; a < 4; ++a) net.fixed[static_cast<size_t>(a)] = true;  // bottom face held
  const Eigen::VectorXd no_load = Eigen::VectorXd::Zero(24);
  for (bool verlet : {true, false}) {
    SpringState state = rest_state(net);
    for (int a = 4; a < 8; ++a) state.x[3 * a + 2] -= 0.1;  // squeeze the top face down
    const double e0 = total_energy(net, state, no_load);
    ASSERT_GT(volume_energy(net, state.x), 0.5 * e0);
    double lowest_top = 1.0, highest_top = 0.0, e_end = 0.0;
    for (int step = 0; step < 2000; ++step) {
      if (verlet)
        step_velocity_verlet(net, state, no_load, 1e-3);
      else
        step_backward_euler(net, state, no_load, 1e-3);
      lowest_top = std::min(lowest_top, state.x[3 * 4 + 2]);
      highest_top = std::max(highest_top, state.x[3 * 4 + 2]);
      e_end = total_energy(net, state, no_load);
      if (verlet) {
        ASSERT_NEAR(e_end, e0, 1e-3 * e0) << "step " << step;
      }
    }
    EXPECT_GT(highest_top, 1.0) << (verlet ? "verlet" : "backward Euler");  // springs back up
    EXPECT_LT(lowest_top, 0.95);
    if (!verlet) {
      EXPECT_LT(e_end, 0.9 * e0);
    }
  }
}

}  // namespace
}  // namespace isospring::analysis
