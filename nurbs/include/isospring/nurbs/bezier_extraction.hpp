#pragma once
// Bezier extraction (Borden, Scott, Evans, Hughes 2011): on element e the B-spline basis is
// N_e(u) = C_e B(u), with B the Bernstein polynomials of the element. Analysis uses it to
// evaluate every element with the same precomputed Bernstein values.
#include <Eigen/Core>
#include <vector>

#include "isospring/nurbs/knot_vector.hpp"

namespace isospring::nurbs {

/// One (p+1) x (p+1) operator per non-empty element, in element order.
std::vector<Eigen::MatrixXd> bezier_extraction(const KnotVector& knots);

/// Bernstein polynomials of degree p on [0, 1] and their first derivatives at t:
/// row 0 values, row 1 derivatives.
Eigen::MatrixXd bernstein(int p, double t);

}  // namespace isospring::nurbs
