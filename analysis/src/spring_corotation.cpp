// Corotated linear forces of a spring network: per-particle rotations by shape matching.
#include "isospring/analysis/spring_corotation.hpp"

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <cmath>
#include <string>

#include "isospring/analysis/spring_mechanics.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::analysis {
namespace {

Eigen::Matrix3d svd_rotation(const Eigen::Matrix3d& a) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(a, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d u = svd.matrixU();
  const Eigen::Matrix3d v = svd.matrixV();
  // A reflection (det < 0) becomes the nearest rotation by flipping the weakest direction.
  if ((u * v.transpose()).determinant() < 0.0) u.col(2) = -u.col(2);
  return u * v.transpose();
}

// Block (i, j) of a sparse d n x d n matrix, accumulated into a dense block list.
struct BlockRows {
  std::vector<std::vector<std::pair<int, Eigen::Matrix3d>>> rows;
  Eigen::Matrix3d& at(int i, int j) {
    for (auto& [column, block] : rows[static_cast<size_t>(i)])
      if (column == j) return block;
    rows[static_cast<size_t>(i)].emplace_back(j, Eigen::Matrix3d::Zero());
    return rows[static_cast<size_t>(i)].back().second;
  }
};

void add_blocks(const Eigen::SparseMatrix<double>& m, int dim, BlockRows& pattern,
                BlockRows& values) {
  for (int c = 0; c < m.outerSize(); ++c)
    for (Eigen::SparseMatrix<double>::InnerIterator it(m, c); it; ++it) {
      const int row = static_cast<int>(it.row()), col = static_cast<int>(it.col());
      pattern.at(row / dim, col / dim);
      values.at(row / dim, col / dim)(row % dim, col % dim) += it.value();
    }
}

}  // namespace

Eigen::Matrix3d polar_rotation(const Eigen::Matrix3d& a) {
  const double det = a.determinant(), size = a.norm();
  // Newton needs an invertible A; below this A is flat (coplanar neighbours) or inverted.
  if (!(det > 1e-9 * size * size * size)) return svd_rotation(a);
  Eigen::Matrix3d r = a;
  for (int iteration = 0; iteration < 40; ++iteration) {
    const Eigen::Matrix3d inverse_t = r.inverse().transpose();
    // Byers-Xu style scaling (Frobenius norms) speeds the first iterations; near convergence it
    // is 1 and the plain iteration converges quadratically.
    const double gamma = iteration < 6 ? std::sqrt(inverse_t.norm() / r.norm()) : 1.0;
    const Eigen::Matrix3d next = 0.5 * (gamma * r + inverse_t / gamma);
    const double change = (next - r).norm();
    r = next;
    if (change < 1e-15) return r;
  }
  return svd_rotation(a);
}

CorotatedForces::CorotatedForces(const SpringNetwork& network) : dim_(network.dimension) {
  const int n = static_cast<int>(network.positions.size());
  rest_ = flat_positions(network);
  BlockRows pattern, k_blocks, c_blocks;
  pattern.rows.resize(static_cast<size_t>(n));
  k_blocks.rows.resize(static_cast<size_t>(n));
  c_blocks.rows.resize(static_cast<size_t>(n));
  add_blocks(rest_stiffness(network), dim_, pattern, k_blocks);
  add_blocks(rest_damping(network), dim_, pattern, c_blocks);
  const size_t bs = static_cast<size_t>(dim_ * dim_);
  offsets_.assign(1, 0);
  auto padded = [this](const double* block) {
    Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
    for (int a = 0; a < dim_; ++a)
      for (int b = 0; b < dim_; ++b) m(a, b) = block[a * dim_ + b];
    return m;
  };
  row_k_.assign(static_cast<size_t>(n) * bs, 0.0);
  row_c_.assign(static_cast<size_t>(n) * bs, 0.0);
  for (int i = 0; i < n; ++i) {
    for (const auto& [j, unused] : pattern.rows[static_cast<size_t>(i)]) {
      const Eigen::Matrix3d k = k_blocks.at(i, j), c = c_blocks.at(i, j);
      for (int a = 0; a < dim_; ++a)
        for (int b = 0; b < dim_; ++b) {
          row_k_[static_cast<size_t>(i) * bs + static_cast<size_t>(a * dim_ + b)] += k(a, b);
          row_c_[static_cast<size_t>(i) * bs + static_cast<size_t>(a * dim_ + b)] += c(a, b);
        }
      if (j == i) continue;
      columns_.push_back(j);
      for (int a = 0; a < dim_; ++a)
        for (int b = 0; b < dim_; ++b) {
          stiffness_.push_back(k(a, b));
          damping_.push_back(c(a, b));
        }
      k3_.push_back(k);
      c3_.push_back(c);
    }
    offsets_.push_back(static_cast<int>(columns_.size()));
    rest_inverse_.push_back(neighbourhood_inverse(i));
    row_k3_.push_back(padded(row_k_.data() + static_cast<size_t>(i) * bs));
    row_c3_.push_back(padded(row_c_.data() + static_cast<size_t>(i) * bs));
    if (offsets_[static_cast<size_t>(i) + 1] == offsets_[static_cast<size_t>(i)] &&
        !pattern.rows[static_cast<size_t>(i)].empty())
      throw nurbs::InputError("corotated forces: particle " + std::to_string(i) +
                              " has terms but no neighbour to measure its rotation from");
  }
}

Eigen::Matrix3d CorotatedForces::neighbourhood_inverse(int i) const {
  Eigen::Matrix3d s = Eigen::Matrix3d::Zero();
  const Eigen::Vector3d ri = rest_point(i);
  for (int e = offsets_[static_cast<size_t>(i)]; e < offsets_[static_cast<size_t>(i) + 1]; ++e) {
    const Eigen::Vector3d dx = rest_point(columns_[static_cast<size_t>(e)]) - ri;
    s.noalias() += dx * dx.transpose();
  }
  // Pseudo-inverse: a flat neighbourhood (2D, or coplanar neighbours) measures in its plane only
  // and the polar decomposition's SVD branch completes the rotation.
  return s.completeOrthogonalDecomposition().pseudoInverse();
}

Eigen::Vector3d CorotatedForces::rest_point(int i) const {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  p.head(dim_) = rest_.segment(static_cast<Eigen::Index>(i) * dim_, dim_);
  return p;
}

void CorotatedForces::rotations(const Eigen::VectorXd& x, std::vector<Eigen::Matrix3d>& out) const {
  const int n = particles(), d = dim_;
  out.resize(static_cast<size_t>(n));
  auto point = [d](const Eigen::VectorXd& flat, int q) {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    p.head(d) = flat.segment(static_cast<Eigen::Index>(q) * d, d);
    return p;
  };
  for (int i = 0; i < n; ++i) {
    const int first = offsets_[static_cast<size_t>(i)], last = offsets_[static_cast<size_t>(i) + 1];
    if (first == last) {  // no terms: nothing to rotate
      out[static_cast<size_t>(i)].setIdentity();
      continue;
    }
    Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
    const Eigen::Vector3d xi = point(x, i), ri = point(rest_, i);
    for (int e = first; e < last; ++e) {
      const int j = columns_[static_cast<size_t>(e)];
      a.noalias() += (point(x, j) - xi) * (point(rest_, j) - ri).transpose();
    }
    // F = A S^-1: the least-squares deformation gradient of the neighbourhood (exact for
    // affine motions, so a pure stretch gives R = I; the polar factor of A itself would turn an
    // anisotropic neighbourhood's stretch into a rotation).
    Eigen::Matrix3d gradient = a * rest_inverse_[static_cast<size_t>(i)];
    if (d == 2) gradient(2, 2) = 1.0;  // in-plane: the rotation is about z
    out[static_cast<size_t>(i)] = polar_rotation(gradient);
  }
}

void CorotatedForces::forces(const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                             Eigen::VectorXd& f) const {
  std::vector<Eigen::Matrix3d> r;
  rotations(x, r);
  rotated_forces(r, x, v, true, f);
}

void CorotatedForces::rotated_forces(const std::vector<Eigen::Matrix3d>& rotations,
                                     const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                                     bool rest_offsets, Eigen::VectorXd& f) const {
  const int n = particles(), d = dim_;
  const bool damped = v.size() == x.size();
  f.setZero(x.size());
  // 2D works in 3D with z = 0 (the padded blocks have zero third rows and columns).
  auto point = [d](const Eigen::VectorXd& flat, int q) {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    p.head(d) = flat.segment(static_cast<Eigen::Index>(q) * d, d);
    return p;
  };
  for (int i = 0; i < n; ++i) {
    const Eigen::Matrix3d& r = rotations[static_cast<size_t>(i)];
    const Eigen::Vector3d xi = point(x, i), ri = point(rest_, i);
    // Local (rotated-back) displacement of i and, per neighbour, of j relative to i.
    Eigen::Vector3d local_i = r.transpose() * xi;
    if (rest_offsets) local_i -= ri;
    Eigen::Vector3d sum = row_k3_[static_cast<size_t>(i)] * local_i;
    Eigen::Vector3d vi = Eigen::Vector3d::Zero();
    if (damped) {
      vi = point(v, i);
      sum += row_c3_[static_cast<size_t>(i)] * (r.transpose() * vi);
    }
    for (int e = offsets_[static_cast<size_t>(i)]; e < offsets_[static_cast<size_t>(i) + 1]; ++e) {
      const int j = columns_[static_cast<size_t>(e)];
      Eigen::Vector3d relative = r.transpose() * (point(x, j) - xi);
      if (rest_offsets) relative -= point(rest_, j) - ri;
      sum += k3_[static_cast<size_t>(e)] * relative;
      if (damped) sum += c3_[static_cast<size_t>(e)] * (r.transpose() * (point(v, j) - vi));
    }
    f.segment(static_cast<Eigen::Index>(i) * d, d) = -(r * sum).head(d);
  }
}

}  // namespace isospring::analysis
