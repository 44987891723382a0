#include "isospring/nurbs/batch_evaluation.hpp"

#include <array>

#include "isospring/nurbs/basis.hpp"

namespace isospring::nurbs {

BatchEvaluator::BatchEvaluator(const Patch& patch)
    : patch_(patch), homogeneous_(4, patch.num_points()) {
  for (int i = 0; i < patch.num_points(); ++i) {
    const double w = patch.weight(i);
    homogeneous_.col(i) << patch.control_point(i) * w, w;
  }
  for (int d = 0; d < patch.param_dim(); ++d) {
    const KnotVector& kv = patch.knots(d);
    Direction& dir = directions_[static_cast<size_t>(d)];
    dir.degree = kv.degree();
    dir.knots = kv.values().data();
    dir.breaks = kv.unique();
    dir.spans = kv.element_spans();
    dir.scale = static_cast<double>(dir.spans.size()) / (kv.last() - kv.first());
    const std::vector<double>& t = kv.values();
    const int p = dir.degree;
    for (int s : dir.spans)
      for (int j = 1; j <= p; ++j)
        for (int r = 0; r < j; ++r)
          dir.inverses.push_back(
              1.0 / (t[static_cast<size_t>(s + r + 1)] - t[static_cast<size_t>(s + 1 - j + r)]));
  }
}

int BatchEvaluator::locate(const Direction& dir, double u, int* element) const {
  // Guess the element as if the knots were uniform, then walk to the right one: exact at once
  // for uniform knots, a few steps otherwise.
  const int last = static_cast<int>(dir.spans.size()) - 1;
  int e = static_cast<int>((u - dir.breaks.front()) * dir.scale);
  e = e < 0 ? 0 : (e > last ? last : e);
  while (e > 0 && u < dir.breaks[static_cast<size_t>(e)]) --e;
  while (e < last && u >= dir.breaks[static_cast<size_t>(e + 1)]) ++e;
  *element = e;
  return dir.spans[static_cast<size_t>(e)];
}

namespace {

/// Values and first derivatives of the p+1 non-zero functions (A2.2 plus eq. 2.9), with the
/// knot-difference reciprocals looked up instead of divided. P > 0 fixes the degree at compile
/// time so the recursion unrolls into registers; P == 0 is the general case.
template <int P>
void basis_with_inverses(int degree, const double* t, int span, const double* inv, double u,
                         double* out) {
  const int p = P > 0 ? P : degree;
  double left[kMaxDegree + 1], right[kMaxDegree + 1];
  double quotient[kMaxDegree + 1] = {};  // degree >= 1 always fills it; zeroed for -Wall
  double* values = out;
  double* derivs = out + p + 1;
  values[0] = 1.0;
  for (int j = 1; j <= p; ++j) {
    left[j] = u - t[span + 1 - j];
    right[j] = t[span + j] - u;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      const double temp = values[r] * *inv++;
      quotient[r] = temp;  // at j = p: N_{span-p+1+r,p-1} / (t_{span+1+r} - t_{span+1-p+r})
      values[r] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    values[j] = saved;
  }
  derivs[0] = -p * quotient[0];
  for (int r = 1; r < p; ++r) derivs[r] = p * (quotient[r - 1] - quotient[r]);
  derivs[p] = p * quotient[p - 1];
}

}  // namespace

void BatchEvaluator::basis(const Direction& dir, int element, double u, double* out) const {
  const int p = dir.degree;
  const int span = dir.spans[static_cast<size_t>(element)];
  const double* inv = dir.inverses.data() + static_cast<size_t>(element) * (p * (p + 1) / 2);
  switch (p) {
    case 1:
      return basis_with_inverses<1>(p, dir.knots, span, inv, u, out);
    case 2:
      return basis_with_inverses<2>(p, dir.knots, span, inv, u, out);
    case 3:
      return basis_with_inverses<3>(p, dir.knots, span, inv, u, out);
    case 4:
      return basis_with_inverses<4>(p, dir.knots, span, inv, u, out);
    case 5:
      return basis_with_inverses<5>(p, dir.knots, span, inv, u, out);
    default:
      return basis_with_inverses<0>(p, dir.knots, span, inv, u, out);
  }
}

namespace {

/// Homogeneous sums over one row of (p+1) control points: value and d/du. W0 > 0 fixes the row
/// width at compile time so the common degrees unroll; W0 == 0 is the general case.
template <int W0>
inline void contract_row(const double* pw, const double* n, const double* dn, int width,
                         Eigen::Vector4d& value, Eigen::Vector4d& derivative) {
  const int w = W0 > 0 ? W0 : width;
  Eigen::Vector4d v = Eigen::Vector4d::Zero(), d = Eigen::Vector4d::Zero();
  for (int i = 0; i < w; ++i) {
    const Eigen::Map<const Eigen::Vector4d> x(pw + 4 * i);
    v.noalias() += n[i] * x;
    d.noalias() += dn[i] * x;
  }
  value = v;
  derivative = d;
}

}  // namespace

void BatchEvaluator::evaluate(const std::vector<Param>& params, Eigen::Matrix3Xd& points,
                              Eigen::Matrix3Xd* first) const {
  const int dim = patch_.param_dim();
  const Eigen::Index count = static_cast<Eigen::Index>(params.size());
  points.resize(3, count);
  if (first) first->resize(3, count * dim);
  constexpr int kW = kMaxDegree + 1;
  const int n0 = patch_.num_points(0), n1 = patch_.num_points(1);
  std::array<int, 3> p{0, 0, 0};
  for (int d = 0; d < dim; ++d) p[static_cast<size_t>(d)] = patch_.degree(d);
  const int w0 = p[0] + 1, w1 = p[1] + 1, w2 = p[2] + 1;
  auto row = w0 == 3   ? &contract_row<3>
             : w0 == 4 ? &contract_row<4>
             : w0 == 5 ? &contract_row<5>
                       : &contract_row<0>;

  for (Eigen::Index q = 0; q < count; ++q) {
    const Param& u = params[static_cast<size_t>(q)];
    // ders[d][0..p] values, ders[d][p+1..2p+1] first derivatives, direction d.
    std::array<std::array<double, 2 * kW>, 3> ders;
    std::array<int, 3> first_index{0, 0, 0};
    for (int d = 0; d < 3; ++d) {
      if (d < dim) {
        const Direction& dir = directions_[static_cast<size_t>(d)];
        int element = 0;
        const int span = locate(dir, u[static_cast<size_t>(d)], &element);
        basis(dir, element, u[static_cast<size_t>(d)], ders[static_cast<size_t>(d)].data());
        first_index[static_cast<size_t>(d)] = span - p[static_cast<size_t>(d)];
      } else {
        ders[static_cast<size_t>(d)][0] = 1.0;  // a constant direction: value 1, derivative 0
        ders[static_cast<size_t>(d)][1] = 0.0;
      }
    }
    const double* N0 = ders[0].data();
    const double* N1 = ders[1].data();
    const double* N2 = ders[2].data();
    // Contract direction u, then v, then w: S[a] holds the homogeneous sum with derivative
    // pattern a (0: value, 1: d/du, 2: d/dv, 3: d/dw).
    Eigen::Vector4d S[4] = {Eigen::Vector4d::Zero(), Eigen::Vector4d::Zero(),
                            Eigen::Vector4d::Zero(), Eigen::Vector4d::Zero()};
    for (int k = 0; k < w2; ++k) {
      Eigen::Vector4d V[3] = {Eigen::Vector4d::Zero(), Eigen::Vector4d::Zero(),
                              Eigen::Vector4d::Zero()};  // value, d/du, d/dv over (i, j)
      for (int j = 0; j < w1; ++j) {
        const int base = first_index[0] + n0 * ((first_index[1] + j) + n1 * (first_index[2] + k));
        Eigen::Vector4d U0, U1;
        row(homogeneous_.data() + 4 * base, N0, N0 + w0, w0, U0, U1);
        V[0].noalias() += N1[j] * U0;
        V[1].noalias() += N1[j] * U1;
        V[2].noalias() += N1[w1 + j] * U0;
      }
      S[0].noalias() += N2[k] * V[0];
      S[1].noalias() += N2[k] * V[1];
      S[2].noalias() += N2[k] * V[2];
      S[3].noalias() += N2[w2 + k] * V[0];
    }
    const double w = S[0].w();
    const Eigen::Vector3d x = S[0].head<3>() / w;
    points.col(q) = x;
    if (first)
      for (int a = 0; a < dim; ++a)
        first->col(dim * q + a) = (S[a + 1].head<3>() - S[a + 1].w() * x) / w;
  }
}

}  // namespace isospring::nurbs
