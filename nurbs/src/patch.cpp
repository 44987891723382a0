#include "isospring/nurbs/patch.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "isospring/nurbs/basis.hpp"
#include "isospring/nurbs/error.hpp"
#include "tensor_basis.hpp"

namespace isospring::nurbs {

Patch::Patch(std::vector<KnotVector> knots, std::vector<Eigen::Vector3d> control_points,
             std::vector<double> weights)
    : knots_(std::move(knots)), points_(std::move(control_points)), weights_(std::move(weights)) {
  if (knots_.empty() || knots_.size() > 3)
    throw InputError("a patch needs 1, 2 or 3 knot vectors (curve, surface, volume), got " +
                     std::to_string(knots_.size()));
  size_t expected = 1;
  for (const auto& kv : knots_) expected *= static_cast<size_t>(kv.num_basis());
  if (points_.size() != expected) {
    std::ostringstream msg;
    msg << "control_points: the knot vectors and degrees give ";
    for (size_t d = 0; d < knots_.size(); ++d) msg << (d ? " x " : "") << knots_[d].num_basis();
    msg << " = " << expected << " control points, but " << points_.size()
        << " are given; add or remove control points or fix the knots";
    throw InputError(msg.str());
  }
  if (weights_.empty()) weights_.assign(points_.size(), 1.0);
  if (weights_.size() != points_.size())
    throw InputError("weights: " + std::to_string(weights_.size()) + " weights for " +
                     std::to_string(points_.size()) +
                     " control points; give one weight per control point (or none for all 1)");
  for (size_t i = 0; i < points_.size(); ++i) {
    if (!points_[i].allFinite())
      throw InputError("control_points[" + std::to_string(i) +
                       "] is not finite (NaN or inf); every coordinate must be a number");
    if (!std::isfinite(weights_[i]) || weights_[i] <= 0.0)
      throw InputError("weights[" + std::to_string(i) + "] = " + std::to_string(weights_[i]) +
                       " must be positive and finite (NURBS weights <= 0 make the geometry "
                       "undefined)");
  }
}

std::array<int, 3> Patch::net_position(int index) const {
  const int n0 = num_points(0), n1 = num_points(1);
  return {index % n0, (index / n0) % n1, index / (n0 * n1)};
}

bool Patch::is_rational() const {
  return std::any_of(weights_.begin(), weights_.end(), [](double w) { return w != 1.0; });
}

int Patch::physical_dim() const {
  if (param_dim() == 3) return 3;
  for (const auto& x : points_)
    if (x.z() != 0.0) return 3;
  return 2;
}

int Patch::num_elements() const {
  int count = 1;
  for (const auto& kv : knots_) count *= kv.num_elements();
  return count;
}

Eigen::Vector3d Patch::point(const Param& u) const {
  return derivatives(u, 0).point;
}

PatchDerivatives Patch::derivatives(const Param& u, int order) const {
  const detail::TensorBasis tb(*this, u, order);
  const int d = param_dim();
  // Homogeneous sums: A (weighted point) and W (weight) for value, first and second derivatives.
  Eigen::Vector4d value = Eigen::Vector4d::Zero();
  std::array<Eigen::Vector4d, 3> first{};
  std::array<std::array<Eigen::Vector4d, 3>, 3> second{};
  for (auto& v : first) v.setZero();
  for (auto& row : second)
    for (auto& v : row) v.setZero();
  tb.for_each([&](int index, const detail::TensorBasis::Values& n) {
    const double w = weights_[static_cast<size_t>(index)];
    Eigen::Vector4d pw;
    pw << points_[static_cast<size_t>(index)] * w, w;
    value += n.value * pw;
    if (order >= 1)
      for (int a = 0; a < d; ++a) first[a] += n.first[a] * pw;
    if (order >= 2)
      for (int a = 0; a < d; ++a)
        for (int b = a; b < d; ++b) second[a][b] += n.second[a][b] * pw;
  });
  PatchDerivatives out;
  const double w = value.w();
  out.point = value.head<3>() / w;
  if (order >= 1)
    for (int a = 0; a < d; ++a)
      out.first.col(a) = (first[a].head<3>() - first[a].w() * out.point) / w;
  if (order >= 2) {
    for (int a = 0; a < d; ++a)
      for (int b = a; b < d; ++b) {
        const Eigen::Vector3d xab =
            (second[a][b].head<3>() - first[a].w() * out.first.col(b) -
             first[b].w() * out.first.col(a) - second[a][b].w() * out.point) /
            w;
        out.second[a].col(b) = xab;
        out.second[b].col(a) = xab;
      }
  }
  return out;
}

RationalBasis Patch::basis(const Param& u, int order) const {
  const detail::TensorBasis tb(*this, u, order);
  const int d = param_dim();
  const int n = tb.count();
  RationalBasis out;
  out.indices.resize(static_cast<size_t>(n));
  out.values.resize(n);
  out.first.setZero(n, order >= 1 ? d : 0);
  out.second.setZero(n, order >= 2 ? d * d : 0);
  // Weighted B-spline products and their sums W, W_a, W_ab.
  double W = 0.0;
  double Wa[3] = {0, 0, 0};
  double Wab[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
  int q = 0;
  tb.for_each([&](int index, const detail::TensorBasis::Values& v) {
    const double w = weights_[static_cast<size_t>(index)];
    out.indices[static_cast<size_t>(q)] = index;
    out.values[q] = v.value * w;
    W += v.value * w;
    for (int a = 0; a < d && order >= 1; ++a) {
      out.first(q, a) = v.first[a] * w;
      Wa[a] += v.first[a] * w;
    }
    for (int a = 0; a < d && order >= 2; ++a)
      for (int b = 0; b < d; ++b) {
        const double nab = a <= b ? v.second[a][b] : v.second[b][a];
        out.second(q, a * d + b) = nab * w;
        Wab[a][b] += nab * w;
      }
    ++q;
  });
  // Quotient rule (The NURBS Book eq. 4.7 generalised to tensor products).
  out.values /= W;
  if (order >= 1)
    for (int a = 0; a < d; ++a) out.first.col(a) = (out.first.col(a) - Wa[a] * out.values) / W;
  if (order >= 2)
    for (int a = 0; a < d; ++a)
      for (int b = 0; b < d; ++b)
        out.second.col(a * d + b) = (out.second.col(a * d + b) - Wa[a] * out.first.col(b) -
                                     Wa[b] * out.first.col(a) - Wab[a][b] * out.values) /
                                    W;
  return out;
}

std::pair<Eigen::Vector3d, Eigen::Vector3d> Patch::control_bounds() const {
  Eigen::Vector3d lo = points_.front(), hi = points_.front();
  for (const auto& x : points_) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  return {lo, hi};
}

}  // namespace isospring::nurbs
