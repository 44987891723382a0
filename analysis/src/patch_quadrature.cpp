// Cached tensor-product quadrature.
#include "patch_quadrature.hpp"

#include "isospring/nurbs/basis.hpp"
#include "isospring/nurbs/quadrature.hpp"

namespace isospring::analysis::detail {

DirectionRule gauss_rule(const nurbs::KnotVector& knots, int points) {
  DirectionRule rule;
  rule.degree = knots.degree();
  rule.points = points;
  const nurbs::GaussRule gauss = nurbs::gauss_legendre(points);
  const int p1 = rule.degree + 1;
  for (int span : knots.element_spans()) {
    rule.spans.push_back(span);
    const double a = knots[span], b = knots[span + 1];
    for (int q = 0; q < points; ++q) {
      const double u = 0.5 * (a + b) + 0.5 * (b - a) * gauss.points[static_cast<size_t>(q)];
      rule.params.push_back(u);
      rule.weights.push_back(0.5 * (b - a) * gauss.weights[static_cast<size_t>(q)]);
      const size_t base = rule.basis.size();
      rule.basis.resize(base + static_cast<size_t>(2 * p1));
      nurbs::basis_derivatives(knots, span, u, 1, rule.basis.data() + base);
    }
  }
  return rule;
}

DirectionRule fixed_rule(const nurbs::KnotVector& knots, double u) {
  DirectionRule rule;
  rule.degree = knots.degree();
  rule.points = 1;
  const int span = knots.find_span(u);
  rule.spans.push_back(span);
  rule.params.push_back(u);
  rule.weights.push_back(1.0);
  rule.basis.resize(static_cast<size_t>(2 * (rule.degree + 1)));
  nurbs::basis_derivatives(knots, span, u, 1, rule.basis.data());
  return rule;
}

PatchQuadrature::PatchQuadrature(const nurbs::Patch& patch, std::array<DirectionRule, 3> rules)
    : patch_(&patch), rules_(std::move(rules)), dim_(patch.param_dim()) {
  num_elements_ = 1;
  points_per_element_ = 1;
  basis_count_ = 1;
  for (int d = 0; d < dim_; ++d) {
    const auto& r = rules_[static_cast<size_t>(d)];
    elements_[static_cast<size_t>(d)] = static_cast<int>(r.spans.size());
    points_[static_cast<size_t>(d)] = r.points;
    order_[static_cast<size_t>(d)] = r.degree + 1;
    num_elements_ *= elements_[static_cast<size_t>(d)];
    points_per_element_ *= r.points;
    basis_count_ *= r.degree + 1;
  }
}

PatchQuadrature PatchQuadrature::volume(const nurbs::Patch& patch, int points) {
  std::array<DirectionRule, 3> rules;
  for (int d = 0; d < patch.param_dim(); ++d)
    rules[static_cast<size_t>(d)] =
        gauss_rule(patch.knots(d), points > 0 ? points : patch.degree(d) + 1);
  return PatchQuadrature(patch, std::move(rules));
}

PatchQuadrature PatchQuadrature::side(const nurbs::Patch& patch, int dir, int end, int points) {
  std::array<DirectionRule, 3> rules;
  for (int d = 0; d < patch.param_dim(); ++d) {
    const auto& knots = patch.knots(d);
    rules[static_cast<size_t>(d)] =
        d == dir ? fixed_rule(knots, end == 0 ? knots.first() : knots.last())
                 : gauss_rule(knots, points > 0 ? points : knots.degree() + 1);
  }
  return PatchQuadrature(patch, std::move(rules));
}

std::array<int, 3> PatchQuadrature::element_position(int element) const {
  return {element % elements_[0], (element / elements_[0]) % elements_[1],
          element / (elements_[0] * elements_[1])};
}

void PatchQuadrature::element_control_points(int element, int* out) const {
  const auto e = element_position(element);
  std::array<int, 3> first{0, 0, 0};
  for (int d = 0; d < dim_; ++d)
    first[static_cast<size_t>(d)] =
        rules_[static_cast<size_t>(d)].spans[static_cast<size_t>(e[static_cast<size_t>(d)])] -
        rules_[static_cast<size_t>(d)].degree;
  int n = 0;
  for (int k = 0; k < order_[2]; ++k)
    for (int j = 0; j < order_[1]; ++j)
      for (int i = 0; i < order_[0]; ++i)
        out[n++] = patch_->index(first[0] + i, first[1] + j, first[2] + k);
}

void PatchQuadrature::evaluate(int element, int point, QuadraturePoint& out) const {
  const auto e = element_position(element);
  const std::array<int, 3> q{point % points_[0], (point / points_[0]) % points_[1],
                             point / (points_[0] * points_[1])};
  // Univariate rows (value, derivative) of each direction; unit rows beyond param_dim.
  static constexpr double kOne[2] = {1.0, 0.0};
  std::array<const double*, 3> rows{kOne, kOne, kOne};
  out.weight = 1.0;
  out.param = {0, 0, 0};
  for (int d = 0; d < dim_; ++d) {
    const auto& r = rules_[static_cast<size_t>(d)];
    const size_t at =
        static_cast<size_t>(e[static_cast<size_t>(d)] * r.points + q[static_cast<size_t>(d)]);
    rows[static_cast<size_t>(d)] = r.basis.data() + at * static_cast<size_t>(2 * (r.degree + 1));
    out.weight *= r.weights[at];
    out.param[static_cast<size_t>(d)] = r.params[at];
  }
  const int n = basis_count_;
  out.values.resize(n);
  out.derivatives.resize(n, dim_);
  thread_local std::vector<int> cps;
  cps.resize(static_cast<size_t>(n));
  element_control_points(element, cps.data());
  // Weighted B-spline products and the weight function W with its derivatives.
  double W = 0.0;
  double dW[3] = {0.0, 0.0, 0.0};
  int a = 0;
  for (int k = 0; k < order_[2]; ++k)
    for (int j = 0; j < order_[1]; ++j)
      for (int i = 0; i < order_[0]; ++i, ++a) {
        const double nu = rows[0][i], nv = rows[1][j], nw = rows[2][k];
        const double w = patch_->weight(cps[static_cast<size_t>(a)]);
        const double value = nu * nv * nw * w;
        out.values[a] = value;
        W += value;
        const double d[3] = {rows[0][order_[0] + i] * nv * nw, nu * rows[1][order_[1] + j] * nw,
                             nu * nv * rows[2][order_[2] + k]};
        for (int c = 0; c < dim_; ++c) {
          out.derivatives(a, c) = d[c] * w;
          dW[c] += d[c] * w;
        }
      }
  out.values /= W;
  for (int c = 0; c < dim_; ++c)
    out.derivatives.col(c) = (out.derivatives.col(c) - dW[c] * out.values) / W;
  out.point.setZero();
  out.jacobian.setZero();
  for (a = 0; a < n; ++a) {
    const Eigen::Vector3d& x = patch_->control_point(cps[static_cast<size_t>(a)]);
    out.point += out.values[a] * x;
    for (int c = 0; c < dim_; ++c) out.jacobian.col(c) += out.derivatives(a, c) * x;
  }
}

}  // namespace isospring::analysis::detail
