#pragma once
// B-spline basis functions and their derivatives (The NURBS Book, algorithms A2.2 and A2.3).
#include <Eigen/Core>
#include <vector>

#include "isospring/nurbs/knot_vector.hpp"

namespace isospring::nurbs {

/// Highest degree the kernel supports (fixed-size scratch space keeps evaluation allocation-free).
inline constexpr int kMaxDegree = 20;

/// The p+1 non-zero basis functions N_{span-p..span}(u) written to out[0..p].
void basis_functions(const KnotVector& knots, int span, double u, double* out);

/// Non-zero basis functions and derivatives up to order n at u: out is row-major (n+1) x (p+1),
/// out[k*(p+1) + j] = d^k/du^k N_{span-p+j}(u). Derivatives above p are zero.
void basis_derivatives(const KnotVector& knots, int span, double u, int n, double* out);

/// Values and first derivatives only (the common case in evaluation and assembly): the same as
/// basis_derivatives(..., 1, ...) but from the degree p-1 functions directly, about 3x cheaper.
/// out[0..p] values, out[p+1..2p+1] derivatives.
void basis_first_derivatives(const KnotVector& knots, int span, double u, double* out);

/// Convenience form of basis_derivatives() returning an (n+1) x (p+1) matrix.
Eigen::MatrixXd basis_derivatives(const KnotVector& knots, double u, int n);

/// Batch evaluation for many parameters: spans[q] and values.block((n+1)*q, 0, n+1, p+1).
struct BasisBatch {
  std::vector<int> spans;
  Eigen::MatrixXd values;
};
BasisBatch basis_derivatives_batch(const KnotVector& knots, const std::vector<double>& params,
                                   int n);

}  // namespace isospring::nurbs
