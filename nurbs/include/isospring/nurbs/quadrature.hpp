#pragma once
// Gauss-Legendre quadrature on [-1, 1] and its tensor products over patch elements.
#include <vector>

namespace isospring::nurbs {

struct GaussRule {
  std::vector<double> points;   // on [-1, 1]
  std::vector<double> weights;  // sum to 2
};

/// n-point Gauss-Legendre rule (exact for polynomials of degree 2n-1), n >= 1, computed by Newton
/// iteration on the Legendre polynomial to machine precision.
GaussRule gauss_legendre(int n);

/// gauss_legendre(n) computed once per thread and kept, for loops that ask for the same few rules
/// millions of times (cut-cell quadrature); the reference stays valid for the thread's lifetime.
const GaussRule& gauss_legendre_cached(int n);

}  // namespace isospring::nurbs
