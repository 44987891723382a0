#pragma once
// Internal: knot refinement of one row of (homogeneous or any vector-valued) control points.
// Shared by tensor-product refinement and Bezier extraction so both rest on one algorithm.
#include <vector>

#include "isospring/nurbs/knot_vector.hpp"

namespace isospring::nurbs::detail {

/// The NURBS Book A5.4 (RefineKnotVectCurve): inserts the sorted knots X into the curve with
/// knot vector kv and control points Pw; returns the new control points and (if asked) knots.
template <class Point>
std::vector<Point> refine_knot_vector_curve(const KnotVector& kv, const std::vector<Point>& Pw,
                                            const std::vector<double>& X,
                                            std::vector<double>* Ubar_out) {
  const std::vector<double>& U = kv.values();
  const int p = kv.degree();
  const int n = static_cast<int>(Pw.size()) - 1;
  const int m = n + p + 1;
  const int r = static_cast<int>(X.size()) - 1;
  const int a = kv.find_span(X.front());
  const int b = kv.find_span(X.back()) + 1;
  std::vector<Point> Qw(Pw.size() + X.size(), Point::Zero(Pw.front().size()));
  std::vector<double> Ubar(U.size() + X.size());
  for (int j = 0; j <= a - p; ++j) Qw[static_cast<size_t>(j)] = Pw[static_cast<size_t>(j)];
  for (int j = b - 1; j <= n; ++j) Qw[static_cast<size_t>(j + r + 1)] = Pw[static_cast<size_t>(j)];
  for (int j = 0; j <= a; ++j) Ubar[static_cast<size_t>(j)] = U[static_cast<size_t>(j)];
  for (int j = b + p; j <= m; ++j) Ubar[static_cast<size_t>(j + r + 1)] = U[static_cast<size_t>(j)];
  int i = b + p - 1;
  int k = b + p + r;
  for (int j = r; j >= 0; --j) {
    while (X[static_cast<size_t>(j)] <= U[static_cast<size_t>(i)] && i > a) {
      Qw[static_cast<size_t>(k - p - 1)] = Pw[static_cast<size_t>(i - p - 1)];
      Ubar[static_cast<size_t>(k)] = U[static_cast<size_t>(i)];
      --k;
      --i;
    }
    Qw[static_cast<size_t>(k - p - 1)] = Qw[static_cast<size_t>(k - p)];
    for (int l = 1; l <= p; ++l) {
      const int ind = k - p + l;
      double alpha = Ubar[static_cast<size_t>(k + l)] - X[static_cast<size_t>(j)];
      if (alpha == 0.0) {
        Qw[static_cast<size_t>(ind - 1)] = Qw[static_cast<size_t>(ind)];
      } else {
        alpha /= Ubar[static_cast<size_t>(k + l)] - U[static_cast<size_t>(i - p + l)];
        Qw[static_cast<size_t>(ind - 1)] =
            alpha * Qw[static_cast<size_t>(ind - 1)] + (1.0 - alpha) * Qw[static_cast<size_t>(ind)];
      }
    }
    Ubar[static_cast<size_t>(k)] = X[static_cast<size_t>(j)];
    --k;
  }
  if (Ubar_out) *Ubar_out = std::move(Ubar);
  return Qw;
}

}  // namespace isospring::nurbs::detail
