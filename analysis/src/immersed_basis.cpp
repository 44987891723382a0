// Background basis of immersed domains at physical points.
#include "immersed_basis.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "isospring/nurbs/basis.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::analysis::detail {

BackgroundBasis::BackgroundBasis(const geometry::ImmersedDomain& domain, bool validate)
    : patch_(&domain.background),
      dim_(domain.dimension),
      origin_(domain.origin),
      extent_(domain.extent),
      frame_(domain.frame),
      rotated_(domain.frame != Eigen::Matrix3d::Identity()) {
  const nurbs::Patch& patch = domain.background;
  if (dim_ != 2 && dim_ != 3)
    throw nurbs::InputError("immersed domain: dimension is " + std::to_string(dim_) +
                            "; it must be 2 or 3");
  if (rotated_ &&
      (dim_ != 3 ||
       ((frame_.transpose() * frame_ - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-12)))
    throw nurbs::InputError(
        "immersed domain: the frame must be a rotation (orthonormal columns), and the identity "
        "in 2D");
  if (patch.param_dim() != dim_)
    throw nurbs::InputError("immersed domain: the background patch has parametric dimension " +
                            std::to_string(patch.param_dim()) + " but the domain is " +
                            std::to_string(dim_) + "D");
  for (int d = 0; d < dim_; ++d) {
    if (!(extent_[d] > 0))
      throw nurbs::InputError("immersed domain: extent must be positive in every direction");
    spans_[static_cast<size_t>(d)] = patch.knots(d).element_spans();
    scale_[static_cast<size_t>(d)] = (patch.param_max(d) - patch.param_min(d)) / extent_[d];
    count_ *= patch.degree(d) + 1;
  }
  // The affine map holds when every control point sits at frame * (origin + extent * (Greville
  // abscissa)) and the weights are equal (a rational box with equal weights is polynomial).
  const double tolerance = 1e-9 * extent_.head(dim_).norm();
  for (int a = 0; validate && a < patch.num_points(); ++a) {
    const auto ijk = patch.net_position(a);
    Eigen::Vector3d expected = origin_;
    for (int d = 0; d < dim_; ++d) {
      const auto& kv = patch.knots(d);
      double g = 0;
      for (int k = 1; k <= kv.degree(); ++k) g += kv[ijk[static_cast<size_t>(d)] + k];
      g /= std::max(1, kv.degree());
      expected[d] += (g - patch.param_min(d)) / scale_[static_cast<size_t>(d)];
    }
    double error = 0;
    for (int d = 0; d < dim_; ++d)
      error = std::max(error, std::abs(patch.control_point(a)[d] - to_world(expected)[d]));
    if (error > tolerance || patch.weight(a) != patch.weight(0)) {
      std::ostringstream message;
      message << "immersed domain: control point " << a
              << " of the background patch is not where the affine box frame (origin + extent * u) "
                 "puts it (or its weight differs): the background must be a uniform-weight "
                 "B-spline box over [origin, origin + extent]";
      throw nurbs::InputError(message.str());
    }
  }
}

double BackgroundBasis::param(int d, double x) const {
  return patch_->param_min(d) + (x - origin_[d]) * scale_[static_cast<size_t>(d)];
}

Element BackgroundBasis::element_of(const Eigen::Vector3d& world) const {
  const Eigen::Vector3d x = to_grid(world);
  Element e{0, 0, 0};
  for (int d = 0; d < dim_; ++d) {
    const int span = patch_->knots(d).find_span(param(d, x[d]));
    const auto& spans = spans_[static_cast<size_t>(d)];
    e[static_cast<size_t>(d)] =
        static_cast<int>(std::upper_bound(spans.begin(), spans.end(), span) - spans.begin() - 1);
    e[static_cast<size_t>(d)] = std::clamp(e[static_cast<size_t>(d)], 0, elements(d) - 1);
  }
  return e;
}

Eigen::Vector3d BackgroundBasis::element_lo(const Element& e) const {
  Eigen::Vector3d x = origin_;
  for (int d = 0; d < dim_; ++d)
    x[d] +=
        (patch_->knots(
             d)[spans_[static_cast<size_t>(d)][static_cast<size_t>(e[static_cast<size_t>(d)])]] -
         patch_->param_min(d)) /
        scale_[static_cast<size_t>(d)];
  return x;
}

Eigen::Vector3d BackgroundBasis::element_hi(const Element& e) const {
  Eigen::Vector3d x = origin_;
  for (int d = 0; d < dim_; ++d)
    x[d] += (patch_->knots(
                 d)[spans_[static_cast<size_t>(d)][static_cast<size_t>(e[static_cast<size_t>(d)])] +
                    1] -
             patch_->param_min(d)) /
            scale_[static_cast<size_t>(d)];
  return x;
}

void BackgroundBasis::control_points(const Element& e, std::vector<int>& out) const {
  std::array<int, 3> first{0, 0, 0}, order{1, 1, 1};
  for (int d = 0; d < dim_; ++d) {
    first[static_cast<size_t>(d)] =
        spans_[static_cast<size_t>(d)][static_cast<size_t>(e[static_cast<size_t>(d)])] - degree(d);
    order[static_cast<size_t>(d)] = degree(d) + 1;
  }
  out.clear();
  for (int k = 0; k < order[2]; ++k)
    for (int j = 0; j < order[1]; ++j)
      for (int i = 0; i < order[0]; ++i)
        out.push_back(patch_->index(first[0] + i, first[1] + j, first[2] + k));
}

namespace {

// Univariate rows: rows[d] holds (k+1) x (p+1) derivatives of direction d (a single 1 beyond
// the dimension).
struct Rows {
  std::array<std::array<double, (nurbs::kMaxDegree + 1) * (nurbs::kMaxDegree + 1)>, 3> data;
  std::array<int, 3> order{1, 1, 1};
};

}  // namespace

void BackgroundBasis::evaluate(const Element& e, const Eigen::Vector3d& world, BasisAt& out) const {
  const Eigen::Vector3d x = to_grid(world);
  Rows rows;
  for (int d = 0; d < 3; ++d) {
    auto& r = rows.data[static_cast<size_t>(d)];
    if (d >= dim_) {
      r[0] = 1.0;
      r[1] = 0.0;
      continue;
    }
    rows.order[static_cast<size_t>(d)] = degree(d) + 1;
    nurbs::basis_derivatives(
        patch_->knots(d),
        spans_[static_cast<size_t>(d)][static_cast<size_t>(e[static_cast<size_t>(d)])],
        param(d, x[d]), 1, r.data());
  }
  control_points(e, out.control_points);
  out.values.resize(count_);
  out.gradients.resize(count_, dim_);
  const auto& o = rows.order;
  const auto& r = rows.data;
  int a = 0;
  for (int k = 0; k < o[2]; ++k)
    for (int j = 0; j < o[1]; ++j)
      for (int i = 0; i < o[0]; ++i, ++a) {
        const double nu = r[0][static_cast<size_t>(i)], nv = r[1][static_cast<size_t>(j)],
                     nw = r[2][static_cast<size_t>(k)];
        out.values[a] = nu * nv * nw;
        out.gradients(a, 0) = r[0][static_cast<size_t>(o[0] + i)] * nv * nw * scale_[0];
        out.gradients(a, 1) = nu * r[1][static_cast<size_t>(o[1] + j)] * nw * scale_[1];
        if (dim_ == 3)
          out.gradients(a, 2) = nu * nv * r[2][static_cast<size_t>(o[2] + k)] * scale_[2];
      }
  // d/dx_j = sum_d d/dy_d dy_d/dx_j with y = frame^T x: each row (a gradient) times frame^T.
  if (rotated_) out.gradients = out.gradients * frame_.transpose();
}

void BackgroundBasis::directional_derivative(const Element& e, const Eigen::Vector3d& world,
                                             int dir, int order, Eigen::VectorXd& out) const {
  const Eigen::Vector3d x = to_grid(world);
  Rows rows;
  std::array<int, 3> row_of{0, 0, 0};  // which derivative row each direction contributes
  for (int d = 0; d < 3; ++d) {
    auto& r = rows.data[static_cast<size_t>(d)];
    if (d >= dim_) {
      r[0] = 1.0;
      continue;
    }
    rows.order[static_cast<size_t>(d)] = degree(d) + 1;
    const int n = d == dir ? order : 0;
    row_of[static_cast<size_t>(d)] = n;
    nurbs::basis_derivatives(
        patch_->knots(d),
        spans_[static_cast<size_t>(d)][static_cast<size_t>(e[static_cast<size_t>(d)])],
        param(d, x[d]), n, r.data());
  }
  const double factor = std::pow(scale_[static_cast<size_t>(dir)], order);
  const auto& o = rows.order;
  const auto& r = rows.data;
  out.resize(count_);
  int a = 0;
  for (int k = 0; k < o[2]; ++k)
    for (int j = 0; j < o[1]; ++j)
      for (int i = 0; i < o[0]; ++i, ++a)
        out[a] = factor * r[0][static_cast<size_t>(row_of[0] * o[0] + i)] *
                 r[1][static_cast<size_t>(row_of[1] * o[1] + j)] *
                 r[2][static_cast<size_t>(row_of[2] * o[2] + k)];
}

}  // namespace isospring::analysis::detail
