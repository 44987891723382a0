#include "isospring/nurbs/basis.hpp"

#include <array>
#include <cassert>

namespace isospring::nurbs {

void basis_functions(const KnotVector& knots, int span, double u, double* out) {
  const int p = knots.degree();
  const double* t = knots.values().data();
  std::array<double, kMaxDegree + 1> left{}, right{};
  out[0] = 1.0;
  for (int j = 1; j <= p; ++j) {
    left[j] = u - t[span + 1 - j];
    right[j] = t[span + j] - u;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      const double temp = out[r] / (right[r + 1] + left[j - r]);
      out[r] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    out[j] = saved;
  }
}

void basis_derivatives(const KnotVector& knots, int span, double u, int n, double* out) {
  const int p = knots.degree();
  assert(p <= kMaxDegree);
  const double* t = knots.values().data();
  constexpr int kStride = kMaxDegree + 1;
  // ndu: basis functions (upper triangle incl. diagonal) and knot differences (lower triangle).
  std::array<double, kStride * kStride> ndu{};
  std::array<double, kStride> left{}, right{};
  std::array<double, 2 * kStride> a{};
  auto NDU = [&](int r, int c) -> double& { return ndu[static_cast<size_t>(r * kStride + c)]; };

  NDU(0, 0) = 1.0;
  for (int j = 1; j <= p; ++j) {
    left[j] = u - t[span + 1 - j];
    right[j] = t[span + j] - u;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      NDU(j, r) = right[r + 1] + left[j - r];
      const double temp = NDU(r, j - 1) / NDU(j, r);
      NDU(r, j) = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    NDU(j, j) = saved;
  }
  const int width = p + 1;
  for (int j = 0; j <= p; ++j) out[j] = NDU(j, p);
  const int top = n < p ? n : p;
  for (int k = top + 1; k <= n; ++k)
    for (int j = 0; j <= p; ++j) out[k * width + j] = 0.0;

  // The NURBS Book A2.3: derivatives from the triangular table, two alternating rows in `a`.
  for (int r = 0; r <= p; ++r) {
    int s1 = 0, s2 = 1;
    a[0] = 1.0;
    for (int k = 1; k <= top; ++k) {
      double d = 0.0;
      const int rk = r - k, pk = p - k;
      if (r >= k) {
        a[s2 * kStride + 0] = a[s1 * kStride + 0] / NDU(pk + 1, rk);
        d = a[s2 * kStride + 0] * NDU(rk, pk);
      }
      const int j1 = rk >= -1 ? 1 : -rk;
      const int j2 = (r - 1 <= pk) ? k - 1 : p - r;
      for (int j = j1; j <= j2; ++j) {
        a[s2 * kStride + j] = (a[s1 * kStride + j] - a[s1 * kStride + j - 1]) / NDU(pk + 1, rk + j);
        d += a[s2 * kStride + j] * NDU(rk + j, pk);
      }
      if (r <= pk) {
        a[s2 * kStride + k] = -a[s1 * kStride + k - 1] / NDU(pk + 1, r);
        d += a[s2 * kStride + k] * NDU(r, pk);
      }
      out[k * width + r] = d;
      std::swap(s1, s2);
    }
  }
  double factor = p;
  for (int k = 1; k <= top; ++k) {
    for (int j = 0; j <= p; ++j) out[k * width + j] *= factor;
    factor *= (p - k);
  }
}

void basis_first_derivatives(const KnotVector& knots, int span, double u, double* out) {
  const int p = knots.degree();
  const double* t = knots.values().data();
  std::array<double, kMaxDegree + 1> left{}, right{}, quotient{};
  double* values = out;
  double* derivs = out + p + 1;
  values[0] = 1.0;
  for (int j = 1; j <= p; ++j) {
    left[j] = u - t[span + 1 - j];
    right[j] = t[span + j] - u;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      // At j = p, temp = N_{span-p+1+r, p-1} / (t_{span+1+r} - t_{span+1-p+r}): exactly the
      // quotients of the derivative formula, so they are kept instead of recomputed.
      const double temp = values[r] / (right[r + 1] + left[j - r]);
      if (j == p) quotient[static_cast<size_t>(r)] = temp;
      values[r] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    values[j] = saved;
  }
  // N'_{i,p} = p (N_{i,p-1} / (t_{i+p} - t_i) - N_{i+1,p-1} / (t_{i+p+1} - t_{i+1})),
  // i = span - p + r (The NURBS Book eq. 2.9).
  if (p == 0) {
    derivs[0] = 0.0;
    return;
  }
  derivs[0] = -p * quotient[0];
  for (int r = 1; r < p; ++r)
    derivs[r] = p * (quotient[static_cast<size_t>(r - 1)] - quotient[static_cast<size_t>(r)]);
  derivs[p] = p * quotient[static_cast<size_t>(p - 1)];
}

Eigen::MatrixXd basis_derivatives(const KnotVector& knots, double u, int n) {
  const int p = knots.degree();
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> ders(n + 1, p + 1);
  basis_derivatives(knots, knots.find_span(u), u, n, ders.data());
  return ders;
}

BasisBatch basis_derivatives_batch(const KnotVector& knots, const std::vector<double>& params,
                                   int n) {
  const int p = knots.degree();
  BasisBatch batch;
  batch.spans.resize(params.size());
  batch.values.resize(static_cast<Eigen::Index>(params.size()) * (n + 1), p + 1);
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> ders(n + 1, p + 1);
  for (size_t q = 0; q < params.size(); ++q) {
    const int span = knots.find_span(params[q]);
    batch.spans[q] = span;
    basis_derivatives(knots, span, params[q], n, ders.data());
    batch.values.block(static_cast<Eigen::Index>(q) * (n + 1), 0, n + 1, p + 1) = ders;
  }
  return batch;
}

}  // namespace isospring::nurbs
