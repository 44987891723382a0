// Forces and stiffness of a spring network. Each spring touches two particles only, so every
// quantity is a loop over springs scattering dimension-sized blocks.
#include "isospring/analysis/spring_mechanics.hpp"

#include <cmath>
#include <string>

#include "isospring/analysis/spring_volume.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::analysis {

namespace {

using Block = Eigen::Matrix3d;

Eigen::Vector3d particle_vector(const Eigen::VectorXd& flat, int q, int dim) {
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  for (int c = 0; c < dim; ++c) v[c] = flat[q * dim + c];
  return v;
}

// Scatters +B on (i,i), (j,j) and -B on (i,j), (j,i).
void add_spring_block(std::vector<Eigen::Triplet<double>>& triplets, int i, int j, int dim,
                      const Block& block) {
  for (int a = 0; a < dim; ++a)
    for (int b = 0; b < dim; ++b) {
      const double value = block(a, b);
      if (value == 0.0) continue;
      triplets.emplace_back(i * dim + a, i * dim + b, value);
      triplets.emplace_back(j * dim + a, j * dim + b, value);
      triplets.emplace_back(i * dim + a, j * dim + b, -value);
      triplets.emplace_back(j * dim + a, i * dim + b, -value);
    }
}

Eigen::SparseMatrix<double> from_triplets(const SpringNetwork& network,
                                          const std::vector<Eigen::Triplet<double>>& triplets) {
  const int n = static_cast<int>(network.positions.size()) * network.dimension;
  Eigen::SparseMatrix<double> matrix(n, n);
  matrix.setFromTriplets(triplets.begin(), triplets.end());
  return matrix;
}

// Direction g_s restricted to one particle: the unit rest direction.
Eigen::Vector3d rest_direction(const SpringNetwork& network, const Spring& s) {
  Eigen::Vector3d l = network.positions[s.i] - network.positions[s.j];
  if (network.dimension == 2) l.z() = 0.0;
  const double length = l.norm();
  return length > 0.0 ? Eigen::Vector3d(l / length) : Eigen::Vector3d::Zero();
}

Eigen::SparseMatrix<double> rest_matrix(const SpringNetwork& network, bool damping) {
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(network.springs.size() * 4 * static_cast<size_t>(network.dimension) *
                   static_cast<size_t>(network.dimension));
  for (const Spring& s : network.springs) {
    const Eigen::Vector3d n = rest_direction(network, s);
    add_spring_block(triplets, s.i, s.j, network.dimension,
                     (damping ? s.damping : s.stiffness) * n * n.transpose());
  }
  // Volume terms are elastic only (no damping of their own).
  if (!damping) add_volume_stiffness(network, Eigen::VectorXd(), true, triplets);
  return from_triplets(network, triplets);
}

}  // namespace

Eigen::VectorXd flat_positions(const SpringNetwork& network) {
  const int dim = network.dimension;
  Eigen::VectorXd x(static_cast<Eigen::Index>(network.positions.size()) * dim);
  for (size_t q = 0; q < network.positions.size(); ++q)
    for (int c = 0; c < dim; ++c)
      x[static_cast<Eigen::Index>(q) * dim + c] = network.positions[q][c];
  return x;
}

double spring_energy(const SpringNetwork& network, const Eigen::VectorXd& x) {
  double energy = 0.0;
  for (const Spring& s : network.springs) {
    const double stretch =
        (particle_vector(x, s.i, network.dimension) - particle_vector(x, s.j, network.dimension))
            .norm() -
        s.rest_length;
    energy += 0.5 * s.stiffness * stretch * stretch;
  }
  return energy + volume_energy(network, x);
}

// The force loops below are the whole cost of an explicit step (10^4 springs at 10^3
// particles): they index the flat vectors directly instead of building 3-vectors per particle,
// which made them ~3x slower.
Eigen::VectorXd spring_forces(const SpringNetwork& network, const Eigen::VectorXd& x) {
  const int dim = network.dimension;
  Eigen::VectorXd f = Eigen::VectorXd::Zero(x.size());
  const double* p = x.data();
  double* out = f.data();
  for (const Spring& s : network.springs) {
    const double* xi = p + static_cast<Eigen::Index>(s.i) * dim;
    const double* xj = p + static_cast<Eigen::Index>(s.j) * dim;
    double l[3] = {xi[0] - xj[0], xi[1] - xj[1], dim == 3 ? xi[2] - xj[2] : 0.0};
    const double length = std::sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
    if (length == 0.0) continue;
    const double scale = -s.stiffness * (length - s.rest_length) / length;
    double* fi = out + static_cast<Eigen::Index>(s.i) * dim;
    double* fj = out + static_cast<Eigen::Index>(s.j) * dim;
    for (int c = 0; c < dim; ++c) {
      fi[c] += scale * l[c];
      fj[c] -= scale * l[c];
    }
  }
  add_volume_forces(network, x, f);
  return f;
}

Eigen::VectorXd damping_forces(const SpringNetwork& network, const Eigen::VectorXd& x,
                               const Eigen::VectorXd& v) {
  const int dim = network.dimension;
  Eigen::VectorXd f = Eigen::VectorXd::Zero(x.size());
  const double* p = x.data();
  const double* w = v.data();
  double* out = f.data();
  for (const Spring& s : network.springs) {
    if (s.damping == 0.0) continue;
    const Eigen::Index i = static_cast<Eigen::Index>(s.i) * dim;
    const Eigen::Index j = static_cast<Eigen::Index>(s.j) * dim;
    double l[3] = {p[i] - p[j], p[i + 1] - p[j + 1], dim == 3 ? p[i + 2] - p[j + 2] : 0.0};
    const double length_squared = l[0] * l[0] + l[1] * l[1] + l[2] * l[2];
    if (length_squared == 0.0) continue;
    double rate = 0.0;  // l . dl/dt: the force on i is -c (l . dl/dt) l / |l|^2
    for (int c = 0; c < dim; ++c) rate += l[c] * (w[i + c] - w[j + c]);
    const double scale = -s.damping * rate / length_squared;
    for (int c = 0; c < dim; ++c) {
      out[i + c] += scale * l[c];
      out[j + c] -= scale * l[c];
    }
  }
  return f;
}

namespace {

// One pass over the springs for both forces, with the dimension a compile-time constant (the
// component loops unroll) and the same operations, in the same order, as spring_forces and
// damping_forces, so each sum is bit-for-bit theirs. Separate passes read the 40-byte springs
// twice; at 10^4 particles (1.3e5 springs) the forces are the whole cost of a Verlet step.
template <int Dim>
void force_pass(const std::vector<Spring>& springs, const double* p, const double* w, double* out,
                double* damp) {
  for (const Spring& s : springs) {
    const Eigen::Index i = static_cast<Eigen::Index>(s.i) * Dim;
    const Eigen::Index j = static_cast<Eigen::Index>(s.j) * Dim;
    const double l[3] = {p[i] - p[j], p[i + 1] - p[j + 1], Dim == 3 ? p[i + 2] - p[j + 2] : 0.0};
    const double length_squared = l[0] * l[0] + l[1] * l[1] + l[2] * l[2];
    if (length_squared == 0.0) continue;  // length == 0 exactly when its square is
    const double length = std::sqrt(length_squared);
    const double scale = -s.stiffness * (length - s.rest_length) / length;
    for (int c = 0; c < Dim; ++c) {
      out[i + c] += scale * l[c];
      out[j + c] -= scale * l[c];
    }
    if (s.damping == 0.0) continue;
    double rate = 0.0;
    for (int c = 0; c < Dim; ++c) rate += l[c] * (w[i + c] - w[j + c]);
    const double damping_scale = -s.damping * rate / length_squared;
    for (int c = 0; c < Dim; ++c) {
      damp[i + c] += damping_scale * l[c];
      damp[j + c] -= damping_scale * l[c];
    }
  }
}

}  // namespace

void spring_and_damping_forces(const SpringNetwork& network, const Eigen::VectorXd& x,
                               const Eigen::VectorXd& v, Eigen::VectorXd& f_spring,
                               Eigen::VectorXd& f_damping) {
  f_spring.setZero(x.size());
  f_damping.setZero(x.size());
  if (network.dimension == 3)
    force_pass<3>(network.springs, x.data(), v.data(), f_spring.data(), f_damping.data());
  else
    force_pass<2>(network.springs, x.data(), v.data(), f_spring.data(), f_damping.data());
  add_volume_forces(network, x, f_spring);
}

Eigen::SparseMatrix<double> tangent_stiffness(const SpringNetwork& network,
                                              const Eigen::VectorXd& x) {
  const int dim = network.dimension;
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(network.springs.size() * 4 * static_cast<size_t>(dim * dim));
  for (const Spring& s : network.springs) {
    const Eigen::Vector3d l = particle_vector(x, s.i, dim) - particle_vector(x, s.j, dim);
    const double length = l.norm();
    if (length == 0.0) continue;
    const Eigen::Vector3d n = l / length;
    const Block nn = n * n.transpose();
    // Only the first `dim` rows/columns are scattered, so the 2D block is the in-plane one.
    const Block block =
        s.stiffness * (nn + (1.0 - s.rest_length / length) * (Block::Identity() - nn));
    add_spring_block(triplets, s.i, s.j, dim, block);
  }
  add_volume_stiffness(network, x, false, triplets);
  return from_triplets(network, triplets);
}

Eigen::SparseMatrix<double> rest_stiffness(const SpringNetwork& network) {
  return rest_matrix(network, false);
}

Eigen::SparseMatrix<double> rest_damping(const SpringNetwork& network) {
  return rest_matrix(network, true);
}

Eigen::VectorXd mass_diagonal(const SpringNetwork& network) {
  const int dim = network.dimension;
  Eigen::VectorXd m(static_cast<Eigen::Index>(network.masses.size()) * dim);
  for (size_t q = 0; q < network.masses.size(); ++q)
    m.segment(static_cast<Eigen::Index>(q) * dim, dim).setConstant(network.masses[q]);
  return m;
}

void assign_damping_alpha(SpringNetwork& network, double alpha) {
  if (!(alpha > 0.0) || !std::isfinite(alpha))
    throw nurbs::InputError("damping alpha = " + std::to_string(alpha) +
                            " is not a positive number; [S15 4.18] uses alpha >= 1 (e.g. 200)");
  for (Spring& s : network.springs)
    s.damping = (1.0 / alpha) * 2.0 *
                std::sqrt(s.stiffness * (network.masses[s.i] + network.masses[s.j])) /
                s.rest_length;
}

void assign_damping_ratio(SpringNetwork& network, double zeta) {
  if (!(zeta >= 0.0) || !std::isfinite(zeta))
    throw nurbs::InputError("damping ratio = " + std::to_string(zeta) +
                            " is not a non-negative number; use e.g. 0.05 for 5% of critical");
  for (Spring& s : network.springs) {
    const double mi = network.masses[s.i], mj = network.masses[s.j];
    // A held end does not move: the oscillator is the other particle alone (infinite mass on
    // the held side, reduced mass -> the free mass).
    const bool fixed_i = !network.fixed.empty() && network.fixed[s.i];
    const bool fixed_j = !network.fixed.empty() && network.fixed[s.j];
    double reduced = mi + mj > 0.0 ? mi * mj / (mi + mj) : 0.0;
    if (fixed_i != fixed_j) reduced = fixed_i ? mj : mi;
    s.damping = 2.0 * zeta * std::sqrt(s.stiffness * reduced);
  }
}

std::vector<int> fixed_dofs(const SpringNetwork& network) {
  std::vector<int> dofs;
  for (size_t q = 0; q < network.fixed.size(); ++q)
    if (network.fixed[q])
      for (int c = 0; c < network.dimension; ++c)
        dofs.push_back(static_cast<int>(q) * network.dimension + c);
  return dofs;
}

}  // namespace isospring::analysis
