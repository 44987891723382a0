// Volume terms of a spring network (header: definition, exactness of the quadrature).
#include "isospring/analysis/spring_volume.hpp"

#include "isospring/analysis/spring_strain_point.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <array>
#include <cmath>

namespace isospring::analysis {

namespace {

// Levi-Civita symbol of three indices in {0, 1, 2}.
double epsilon(int i, int j, int k) {
  return static_cast<double>((i - j) * (j - k) * (k - i)) / 2.0;
}

// d N_a / d xi_m at xi for corner a (tensor order: bit m of a is the corner's coordinate m).
double shape_derivative(int a, int m, const double* xi, int dim) {
  double value = 1.0;
  for (int d = 0; d < dim; ++d) {
    const bool upper = ((a >> d) & 1) != 0;
    if (d == m)
      value *= upper ? 1.0 : -1.0;
    else
      value *= upper ? xi[d] : 1.0 - xi[d];
  }
  return value;
}

// corner_x: the corners' coordinates, corner-major (corner a, component i -> a * Dim + i).
template <int Dim>
double cell_volume_fixed(const double* corner_x, Eigen::VectorXd* gradient,
                         Eigen::MatrixXd* hessian) {
  constexpr int corners = 1 << Dim;
  constexpr int size = corners * Dim;
  const double g = 0.5 / std::sqrt(3.0);
  const double points[2] = {0.5 - g, 0.5 + g};
  const double weight = 1.0 / static_cast<double>(corners);  // (1/2)^Dim per Gauss point
  if (gradient) gradient->setZero(size);
  if (hessian) hessian->setZero(size, size);
  double volume = 0.0;
  for (int p = 0; p < corners; ++p) {
    double xi[3] = {0.0, 0.0, 0.0};
    for (int d = 0; d < Dim; ++d) xi[d] = points[(p >> d) & 1];
    Eigen::Matrix<double, corners, Dim> dn;  // dN_a / dxi_m
    for (int a = 0; a < corners; ++a)
      for (int m = 0; m < Dim; ++m) dn(a, m) = shape_derivative(a, m, xi, Dim);
    Eigen::Matrix<double, Dim, Dim> j = Eigen::Matrix<double, Dim, Dim>::Zero();
    for (int a = 0; a < corners; ++a)
      for (int i = 0; i < Dim; ++i)
        for (int m = 0; m < Dim; ++m) j(i, m) += corner_x[a * Dim + i] * dn(a, m);
    volume += weight * j.determinant();
    if (!gradient && !hessian) continue;
    // Cofactors d det J / d J_im.
    Eigen::Matrix<double, Dim, Dim> cof;
    if constexpr (Dim == 2) {
      cof << j(1, 1), -j(1, 0), -j(0, 1), j(0, 0);
    } else {
      for (int m = 0; m < 3; ++m) {
        const Eigen::Vector3d c = j.col((m + 1) % 3).cross(j.col((m + 2) % 3));
        cof.col(m) = c;
      }
    }
    if (gradient)
      for (int a = 0; a < corners; ++a)
        for (int i = 0; i < Dim; ++i)
          (*gradient)[a * Dim + i] += weight * cof.row(i).dot(dn.row(a));
    if (!hessian) continue;
    // d2 det J / dJ_im dJ_jn: 2D eps_ij eps_mn; 3D sum_kl eps_ijk eps_mnl J_kl.
    for (int i = 0; i < Dim; ++i)
      for (int jj = 0; jj < Dim; ++jj)
        for (int m = 0; m < Dim; ++m)
          for (int n = 0; n < Dim; ++n) {
            double second = 0.0;
            if constexpr (Dim == 2) {
              second = static_cast<double>((jj - i) * (n - m));  // eps_ij eps_mn in 2D
            } else {
              for (int k = 0; k < 3; ++k)
                for (int l = 0; l < 3; ++l)
                  second += epsilon(i, jj, k) * epsilon(m, n, l) * j(k, l);
            }
            if (second == 0.0) continue;
            for (int a = 0; a < corners; ++a)
              for (int b = 0; b < corners; ++b)
                (*hessian)(a * Dim + i, b * Dim + jj) += weight * second * dn(a, m) * dn(b, n);
          }
  }
  return volume;
}

// Orthonormal basis of the symmetric deviatoric d x d tensors (5 in 3D, 2 in 2D).
template <int Dim>
std::vector<Eigen::Matrix<double, Dim, Dim>> deviatoric_basis() {
  using M = Eigen::Matrix<double, Dim, Dim>;
  std::vector<M> basis;
  const double r2 = 1.0 / std::sqrt(2.0);
  for (int i = 0; i < Dim; ++i)
    for (int j = i + 1; j < Dim; ++j) {
      M m = M::Zero();
      m(i, j) = m(j, i) = r2;
      basis.push_back(m);
    }
  M m = M::Zero();
  m(0, 0) = r2;
  m(1, 1) = -r2;
  basis.push_back(m);
  if constexpr (Dim == 3) {
    M n = M::Zero();
    n(0, 0) = n(1, 1) = 1.0 / std::sqrt(6.0);
    n(2, 2) = -2.0 / std::sqrt(6.0);
    basis.push_back(n);
  }
  return basis;
}

// Shear term at the corners' coordinates x (corner-major): energy mu |V0| |dev G|^2 with
// F = sum_a x_a h_a^T, h_a = b_a / V0 (b: the rest volume gradient), G = (F^T F - I) / 2;
// gradient and Hessian with respect to x when not null.
template <int Dim>
double shear_energy_fixed(const double* corner_x, const Eigen::VectorXd& rest_b, double v0,
                          double mu, Eigen::VectorXd* gradient, Eigen::MatrixXd* hessian) {
  using M = Eigen::Matrix<double, Dim, Dim>;
  using V = Eigen::Matrix<double, Dim, 1>;
  constexpr int corners = 1 << Dim;
  std::array<V, corners> h;
  M f = M::Zero();
  for (int a = 0; a < corners; ++a) {
    h[a] = rest_b.segment<Dim>(a * Dim) / v0;
    f += Eigen::Map<const V>(corner_x + a * Dim) * h[a].transpose();
  }
  const M identity = M::Identity();
  auto dev = [&](const M& m) { return M(m - m.trace() / Dim * identity); };
  const M g = 0.5 * (f.transpose() * f - identity);
  const M dg = dev(g);
  const double scale = mu * std::abs(v0);
  if (gradient) {
    const M p = 2.0 * scale * f * dg;  // dE/dF
    gradient->resize(corners * Dim);
    for (int a = 0; a < corners; ++a) gradient->segment<Dim>(a * Dim) = p * h[a];
  }
  if (hessian) {
    hessian->resize(corners * Dim, corners * Dim);
    for (int b = 0; b < corners; ++b)
      for (int j = 0; j < Dim; ++j) {
        const M df = V::Unit(j) * h[b].transpose();
        const M dsym = 0.5 * (f.transpose() * df + df.transpose() * f);
        const M dp = 2.0 * scale * (df * dg + f * dev(dsym));
        for (int a = 0; a < corners; ++a) hessian->block<Dim, 1>(a * Dim, b * Dim + j) = dp * h[a];
      }
  }
  return scale * dg.squaredNorm();
}

template <int Dim>
std::vector<Eigen::VectorXd> shear_columns_fixed(const Eigen::VectorXd& b, double factor) {
  // A cell's corners or a strain point's control points.
  const auto corners = static_cast<int>(b.size()) / Dim;
  std::vector<Eigen::VectorXd> columns;
  for (const auto& d : deviatoric_basis<Dim>()) {
    Eigen::VectorXd g(corners * Dim);
    for (int a = 0; a < corners; ++a) {
      const Eigen::Matrix<double, Dim, 1> b_a = b.segment<Dim>(a * Dim);
      const Eigen::Matrix<double, Dim, 1> column = factor * (d * b_a);
      for (int i = 0; i < Dim; ++i) g[a * Dim + i] = column[i];
    }
    columns.push_back(g);
  }
  return columns;
}

}  // namespace

int volume_corners(int dimension) {
  return dimension == 2 ? 4 : 8;
}

double cell_volume(const VolumeTerm& term, const Eigen::VectorXd& x, int dimension,
                   Eigen::VectorXd* gradient, Eigen::MatrixXd* hessian) {
  if (!term.points.empty()) return strain_point_volume(term, x, dimension, gradient, hessian);
  double corner_x[24];
  for (int a = 0; a < volume_corners(dimension); ++a)
    for (int c = 0; c < dimension; ++c)
      corner_x[a * dimension + c] =
          x[static_cast<Eigen::Index>(term.particles[static_cast<size_t>(a)]) * dimension + c];
  return dimension == 2 ? cell_volume_fixed<2>(corner_x, gradient, hessian)
                        : cell_volume_fixed<3>(corner_x, gradient, hessian);
}

double rest_cell_volume(const SpringNetwork& network, const VolumeTerm& term,
                        Eigen::VectorXd* gradient) {
  const int dim = network.dimension;
  if (!term.points.empty()) {
    if (gradient) *gradient = strain_point_rest_gradient(term, dim);
    return term.rest_volume;
  }
  double corner_x[24];
  for (int a = 0; a < volume_corners(dim); ++a)
    for (int c = 0; c < dim; ++c)
      corner_x[a * dim + c] = network.positions[static_cast<size_t>(term.particles[a])][c];
  return dim == 2 ? cell_volume_fixed<2>(corner_x, gradient, nullptr)
                  : cell_volume_fixed<3>(corner_x, gradient, nullptr);
}

std::vector<int> volume_dofs(const VolumeTerm& term, int dimension) {
  std::vector<int> dofs;
  for (int p : term.points)
    for (int c = 0; c < dimension; ++c) dofs.push_back(p * dimension + c);
  if (!term.points.empty()) return dofs;
  for (int a = 0; a < volume_corners(dimension); ++a)
    for (int c = 0; c < dimension; ++c)
      dofs.push_back(term.particles[static_cast<size_t>(a)] * dimension + c);
  return dofs;
}

namespace {

// The corners' coordinates of a term at x, corner-major.
void corner_coordinates(const VolumeTerm& term, const Eigen::VectorXd& x, int dimension,
                        double* corner_x) {
  for (int a = 0; a < volume_corners(dimension); ++a)
    for (int c = 0; c < dimension; ++c)
      corner_x[a * dimension + c] =
          x[static_cast<Eigen::Index>(term.particles[static_cast<size_t>(a)]) * dimension + c];
}

}  // namespace

double cell_shear_energy(const SpringNetwork& network, const VolumeTerm& term,
                         const Eigen::VectorXd& x, Eigen::VectorXd* gradient,
                         Eigen::MatrixXd* hessian) {
  if (!term.points.empty())
    return strain_point_shear_energy(term, x, network.dimension, gradient, hessian);
  Eigen::VectorXd b;
  const double v0 = rest_cell_volume(network, term, &b);
  double corner_x[24];
  corner_coordinates(term, x, network.dimension, corner_x);
  return network.dimension == 2
             ? shear_energy_fixed<2>(corner_x, b, v0, term.modulus, gradient, hessian)
             : shear_energy_fixed<3>(corner_x, b, v0, term.modulus, gradient, hessian);
}

std::vector<Eigen::VectorXd> rest_stiffness_columns(const SpringNetwork& network,
                                                    const VolumeTerm& term) {
  const int dim = network.dimension;
  Eigen::VectorXd b;
  const double v0 = std::abs(rest_cell_volume(network, term, &b));
  if (term.kind == CellEnergy::kVolume) return {b / std::sqrt(v0)};
  // E = mu |V0| sum_k eps_k^2 with eps_k = D_k : eps = sum_a u_a . D_k b_a / V0 (D_k an
  // orthonormal deviatoric basis), so K = 2 mu |V0| sum_k c_k c_k^T = mu sum_k g_k g_k^T with
  // g_k = sqrt(2 / |V0|) (D_k b_a)_a.
  const double factor = std::sqrt(2.0 / v0);
  return dim == 2 ? shear_columns_fixed<2>(b, factor) : shear_columns_fixed<3>(b, factor);
}

double volume_energy(const SpringNetwork& network, const Eigen::VectorXd& x) {
  double energy = 0.0;
  for (const VolumeTerm& t : network.volumes) {
    if (t.kind == CellEnergy::kShear) {
      energy += cell_shear_energy(network, t, x);
      continue;
    }
    const double change = cell_volume(t, x, network.dimension) - t.rest_volume;
    energy += 0.5 * t.modulus / std::abs(t.rest_volume) * change * change;
  }
  return energy;
}

void add_volume_forces(const SpringNetwork& network, const Eigen::VectorXd& x, Eigen::VectorXd& f) {
  Eigen::VectorXd b;
  for (const VolumeTerm& t : network.volumes) {
    const std::vector<int> dofs = volume_dofs(t, network.dimension);
    if (t.kind == CellEnergy::kShear) {
      cell_shear_energy(network, t, x, &b);
      for (size_t e = 0; e < dofs.size(); ++e) f[dofs[e]] -= b[static_cast<Eigen::Index>(e)];
      continue;
    }
    const double change = cell_volume(t, x, network.dimension, &b) - t.rest_volume;
    const double scale = -t.modulus / std::abs(t.rest_volume) * change;
    for (size_t e = 0; e < dofs.size(); ++e) f[dofs[e]] += scale * b[static_cast<Eigen::Index>(e)];
  }
}

void add_volume_stiffness(const SpringNetwork& network, const Eigen::VectorXd& x, bool at_rest,
                          std::vector<Eigen::Triplet<double>>& triplets) {
  Eigen::VectorXd b;
  Eigen::MatrixXd h;
  for (const VolumeTerm& t : network.volumes) {
    const double factor = t.modulus / std::abs(t.rest_volume);
    Eigen::MatrixXd block;
    if (t.kind == CellEnergy::kShear) {
      if (at_rest) {
        const auto size = static_cast<Eigen::Index>(volume_dofs(t, network.dimension).size());
        block = Eigen::MatrixXd::Zero(size, size);
        for (const Eigen::VectorXd& g : rest_stiffness_columns(network, t))
          block += t.modulus * g * g.transpose();
      } else {
        cell_shear_energy(network, t, x, nullptr, &block);
      }
    } else if (at_rest) {
      rest_cell_volume(network, t, &b);
      block = factor * b * b.transpose();
    } else {
      const double change = cell_volume(t, x, network.dimension, &b, &h) - t.rest_volume;
      block = factor * (b * b.transpose() + change * h);
    }
    const std::vector<int> dofs = volume_dofs(t, network.dimension);
    for (size_t r = 0; r < dofs.size(); ++r)
      for (size_t c = 0; c < dofs.size(); ++c) {
        const double value = block(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c));
        if (value != 0.0) triplets.emplace_back(dofs[r], dofs[c], value);
      }
  }
}

}  // namespace isospring::analysis
