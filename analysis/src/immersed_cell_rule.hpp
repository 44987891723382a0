#pragma once
// A cell's quadrature reduced to the points of one tensor rule on its background element, exact
// for every integrand the bilinear forms of the analysis produce there.
//
// On a background element the basis functions are polynomials of degree p_d in each direction d
// (the grid is an affine B-spline box), so every bulk integrand of the linear analysis (products
// of two values or gradients: stiffness, body load, strain energy, the reaction's sigma grad psi)
// lies in Q_2p, the tensor polynomials of degree 2 p_d per direction. On the tensor grid of
// n_d = 2 p_d + 1 Gauss-Legendre nodes per direction, Lagrange interpolation reproduces Q_2p, so
// the weights W_k = sum_q w_q L_k(x_q) (L_k the tensor Lagrange polynomials of the nodes x_k)
// give sum_k W_k f(x_k) = sum_q w_q f(x_q) for every f in Q_2p: the same integrals up to
// round-off, from (2p + 1)^d points however many the cut cell had (bisected cut cells carry
// thousands). The weights may be negative; the integrals are what they were.
//
// Not for integrands outside Q_2p (errors against a closed form): those keep the cell's points.
#include <Eigen/Core>
#include <vector>

#include "immersed_basis.hpp"

namespace isospring::analysis::detail {

struct CellRule {
  std::vector<Eigen::Vector3d> points;
  std::vector<double> weights;
};

/// The cell's rule on element `e`: the reduced rule when it has fewer points than the cell's
/// own, else the cell's own points and weights (inside cells keep their (p + 1)^d Gauss points).
CellRule reduced_cell_rule(const BackgroundBasis& basis, const Element& e,
                           const std::vector<Eigen::Vector3d>& points,
                           const std::vector<double>& weights);

}  // namespace isospring::analysis::detail
