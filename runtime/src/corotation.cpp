// Corotated forces of a reduced model: per-particle rotations by shape matching, the rest
// blocks applied in those frames, projected on the basis (corotation.hpp).
#include "corotation.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <string>

#include "json_fields.hpp"

namespace isospring::runtime {
namespace {

using nlohmann::json;

Eigen::Matrix3d svd_rotation(const Eigen::Matrix3d& a) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(a, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d u = svd.matrixU();
  const Eigen::Matrix3d v = svd.matrixV();
  if ((u * v.transpose()).determinant() < 0.0) u.col(2) = -u.col(2);
  return u * v.transpose();
}

// The rotation of A's polar decomposition: scaled Newton, the SVD for a flat or inverted A
// (analysis::polar_rotation).
Eigen::Matrix3d polar_rotation(const Eigen::Matrix3d& a) {
  const double det = a.determinant(), size = a.norm();
  if (!(det > 1e-9 * size * size * size)) return svd_rotation(a);
  Eigen::Matrix3d r = a;
  for (int iteration = 0; iteration < 40; ++iteration) {
    const Eigen::Matrix3d inverse_t = r.inverse().transpose();
    const double gamma = iteration < 6 ? std::sqrt(inverse_t.norm() / r.norm()) : 1.0;
    const Eigen::Matrix3d next = 0.5 * (gamma * r + inverse_t / gamma);
    const double change = (next - r).norm();
    r = next;
    if (change < 1e-15) return r;
  }
  return svd_rotation(a);
}

Eigen::Matrix3d padded(const double* block, int d) {
  Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
  for (int a = 0; a < d; ++a)
    for (int b = 0; b < d; ++b) m(a, b) = block[a * d + b];
  return m;
}

Eigen::Vector3d point(const double* flat, size_t q, int d) {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (int c = 0; c < d; ++c) p[c] = flat[q * static_cast<size_t>(d) + static_cast<size_t>(c)];
  return p;
}

// Rows of `count` entries of d * d numbers each, flattened into out.
void read_blocks(const json& rows, const std::string& name, const std::vector<int>& offsets, int d,
                 const JsonFields& fields, std::vector<double>& out) {
  const size_t particles = offsets.size() - 1, bs = static_cast<size_t>(d * d);
  fields.array(rows, name, particles);
  for (size_t i = 0; i < particles; ++i) {
    const size_t count = static_cast<size_t>(offsets[i + 1] - offsets[i]) * bs;
    const std::string row = name + "[" + std::to_string(i) + "]";
    const json& entries = fields.array(rows[i], row, count);
    for (size_t k = 0; k < count; ++k)
      out.push_back(fields.number(entries[k], row + "[" + std::to_string(k) + "]"));
  }
}

// x = X + Phi q (or Phi q), v = Phi qdot into the scratch; the rotations at x_rot.
void expand(const Model& model, const double* q, bool add_rest, std::vector<double>& out) {
  const size_t r = model.basis_size, rows = model.basis.size() / r;
  for (size_t d = 0; d < rows; ++d) {
    const double* row = model.basis.data() + d * r;
    double sum = add_rest ? model.rest[d] : 0.0;
    for (size_t k = 0; k < r; ++k) sum += row[k] * q[k];
    out[d] = sum;
  }
}

void project(const Model& model, const std::vector<double>& f, double* g) {
  const size_t r = model.basis_size, rows = model.basis.size() / r;
  for (size_t k = 0; k < r; ++k) g[k] = 0.0;
  for (size_t d = 0; d < rows; ++d) {
    const double fd = f[d];
    const double* row = model.basis.data() + d * r;
    for (size_t k = 0; k < r; ++k) g[k] += row[k] * fd;
  }
}

void rotations(const Model& model) {
  const int d = model.dimension;
  const double* x = model.corot_x.data();
  for (size_t i = 0; i < model.particles; ++i) {
    Eigen::Matrix3d& out = model.corot_rotations[i];
    const int first = model.corot_offsets[i], last = model.corot_offsets[i + 1];
    if (first == last) {
      out.setIdentity();
      continue;
    }
    Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
    const Eigen::Vector3d xi = point(x, i, d), ri = point(model.rest.data(), i, d);
    for (int e = first; e < last; ++e) {
      const auto j = static_cast<size_t>(model.corot_columns[static_cast<size_t>(e)]);
      a.noalias() += (point(x, j, d) - xi) * (point(model.rest.data(), j, d) - ri).transpose();
    }
    Eigen::Matrix3d gradient = a * padded(model.corot_rest_inverse.data() + i * d * d, d);
    if (d == 2) gradient(2, 2) = 1.0;
    out = polar_rotation(gradient);
  }
}

// f_i = -R_i sum_j [K_ij l_ij + C_ij R_i^T v_ij] over the differences (analysis::CorotatedForces);
// returns the energy 1/2 sum_i l_i . sum_j K_ij l_j when `rest_offsets`.
double rotated_forces(const Model& model, bool rest_offsets, bool damped) {
  const int d = model.dimension;
  const size_t bs = static_cast<size_t>(d * d);
  const double *x = model.corot_x.data(), *v = model.corot_v.data(), *rest = model.rest.data();
  double energy = 0.0;
  for (size_t i = 0; i < model.particles; ++i) {
    const Eigen::Matrix3d& r = model.corot_rotations[i];
    const Eigen::Vector3d xi = point(x, i, d), ri = point(rest, i, d);
    Eigen::Vector3d local_i = r.transpose() * xi;
    if (rest_offsets) local_i -= ri;
    Eigen::Vector3d elastic = padded(model.corot_row_stiffness.data() + i * bs, d) * local_i;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero(), vi = Eigen::Vector3d::Zero();
    if (damped) {
      vi = point(v, i, d);
      sum += padded(model.corot_row_damping.data() + i * bs, d) * (r.transpose() * vi);
    }
    for (int e = model.corot_offsets[i]; e < model.corot_offsets[i + 1]; ++e) {
      const auto j = static_cast<size_t>(model.corot_columns[static_cast<size_t>(e)]);
      Eigen::Vector3d relative = r.transpose() * (point(x, j, d) - xi);
      if (rest_offsets) relative -= point(rest, j, d) - ri;
      elastic += padded(model.corot_stiffness.data() + static_cast<size_t>(e) * bs, d) * relative;
      if (damped)
        sum += padded(model.corot_damping.data() + static_cast<size_t>(e) * bs, d) *
               (r.transpose() * (point(v, j, d) - vi));
    }
    energy += 0.5 * local_i.dot(elastic);
    const Eigen::Vector3d f = -(r * (elastic + sum));
    for (int c = 0; c < d; ++c)
      model.corot_f[i * static_cast<size_t>(d) + static_cast<size_t>(c)] = f[c];
  }
  return energy;
}

}  // namespace

void read_corotation(const json& corotation, const JsonFields& fields, Model& model) {
  if (!corotation.is_object()) fields.fail("corotation", "must be an object");
  const int d = model.dimension;
  const size_t n = model.particles;
  const json& neighbours = fields.array(fields.require(corotation, "neighbours", "corotation."),
                                        "corotation.neighbours", n);
  model.corot_offsets.assign(1, 0);
  for (size_t i = 0; i < n; ++i) {
    const std::string row = "corotation.neighbours[" + std::to_string(i) + "]";
    if (!neighbours[i].is_array()) fields.fail(row, "must be an array of particle indices");
    for (size_t k = 0; k < neighbours[i].size(); ++k)
      model.corot_columns.push_back(
          fields.index(neighbours[i][k], row + "[" + std::to_string(k) + "]", n));
    model.corot_offsets.push_back(static_cast<int>(model.corot_columns.size()));
  }
  read_blocks(fields.require(corotation, "stiffness", "corotation."), "corotation.stiffness",
              model.corot_offsets, d, fields, model.corot_stiffness);
  read_blocks(fields.require(corotation, "damping", "corotation."), "corotation.damping",
              model.corot_offsets, d, fields, model.corot_damping);
  // Per-particle d x d matrices: one "neighbour" each.
  std::vector<int> single(n + 1);
  for (size_t i = 0; i <= n; ++i) single[i] = static_cast<int>(i);
  read_blocks(fields.require(corotation, "row_stiffness", "corotation."),
              "corotation.row_stiffness", single, d, fields, model.corot_row_stiffness);
  read_blocks(fields.require(corotation, "row_damping", "corotation."), "corotation.row_damping",
              single, d, fields, model.corot_row_damping);
  read_blocks(fields.require(corotation, "rest_inverse", "corotation."), "corotation.rest_inverse",
              single, d, fields, model.corot_rest_inverse);
  model.corot_x.assign(n * static_cast<size_t>(d), 0.0);
  model.corot_v = model.corot_f = model.corot_x;
  model.corot_rotations.assign(n, Eigen::Matrix3d::Identity());
}

double corotated_reduced_force(const Model& model, const double* q, const double* qdot, double* g) {
  expand(model, q, true, model.corot_x);
  if (qdot) expand(model, qdot, false, model.corot_v);
  rotations(model);
  const double energy = rotated_forces(model, true, qdot != nullptr);
  project(model, model.corot_f, g);
  return energy;
}

void corotated_reduced_jvp(const Model& model, const double* q, const double* dq,
                           const double* dqdot, double* dg) {
  expand(model, q, true, model.corot_x);
  rotations(model);
  // The derivative at frozen rotations: the same pass on (dx, dv) without the rest offsets.
  if (dq)
    expand(model, dq, false, model.corot_x);
  else
    std::fill(model.corot_x.begin(), model.corot_x.end(), 0.0);
  if (dqdot) expand(model, dqdot, false, model.corot_v);
  rotated_forces(model, false, dqdot != nullptr);
  project(model, model.corot_f, dg);
}

}  // namespace isospring::runtime
