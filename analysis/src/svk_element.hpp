#pragma once
// The St. Venant-Kirchhoff element kernel of SvkAssembler: internal force split by Lame parameter
// and the consistent tangent of one element, from the element's basis gradients at its
// quadrature points (evaluated once per element, see ElementGradients).
#include <Eigen/Core>
#include <array>

#include "isospring/analysis/elasticity.hpp"
#include "patch_quadrature.hpp"

namespace isospring::analysis::detail {

/// The physical basis gradients and integration weights of one element.
struct ElementGradients {
  /// n x (dim * nq): columns q * dim + j hold dR_a/dX_j at quadrature point q.
  Eigen::MatrixXd gradients;
  /// nq: Gauss weight * det J * thickness at each point.
  Eigen::VectorXd weights;
};

/// Evaluates ElementGradients of element `element` of patch `patch` (dim = 2 or 3). Throws
/// nurbs::InputError for an inverted parametrisation (detail::physical_gradients).
void element_gradients(const PatchQuadrature& quadrature, int patch, int element, int dim,
                       double thickness, QuadraturePoint& point, ElementGradients& out);

/// Work buffers of svk_element, reused across elements by one thread.
struct SvkElementScratch {
  Eigen::MatrixXd weighted;                 // n x (dim * nq): G_q T_ii(q) of one diagonal block
  Eigen::MatrixXd stacked;                  // the same of the off-diagonal blocks, stacked
  std::array<Eigen::MatrixXd, 3> diagonal;  // n x n: blocks (i, i), lower triangles
  Eigen::MatrixXd off_diagonal;             // blocks (i, k), i < k, stacked (n rows each)
  Eigen::MatrixXd deformation;              // dim x (dim * nq): F at every point
  Eigen::MatrixXd stress;                   // dim x (dim * nq): S at every point
};

/// Element forces of unit lambda (S = tr(E) I) and unit mu (S = 2 E), each of size n * Dim
/// (local DOF a * Dim + i), and, when `tangent` is not null, the element tangent for `lame` (full
/// symmetric, n * Dim square). `displacements` holds the element's nodal displacements, row a =
/// u_a (n x Dim).
///
/// The tangent is K_(a,i),(b,k) = sum_q G_a^T T_ik G_b with G_a = dR_a/dX at point q and the
/// Dim x Dim matrix T_ik = w (lambda f_i f_k^T + mu f_k f_i^T + mu (F F^T)_ik I + delta_ik S),
/// f_i the i-th row of F: the first elasticity tensor dP_iJ/dF_kL contracted block by block. Each
/// block (i, k) is then one product (G T_ik over all points) G^T of n x n x Dim nq multiply-adds;
/// symmetry leaves the lower triangles of the Dim diagonal blocks and the Dim (Dim - 1) / 2 blocks
/// above them: 3.6 M multiply-adds for a degree-3 solid element (n = nq = 64), against 7.1 M when
/// the terms of the formula were formed apart (13 products over the points).
template <int Dim>
void svk_element(const ElementGradients& element, const Eigen::MatrixXd& displacements,
                 const LameParameters& lame, Eigen::VectorXd& force_lambda,
                 Eigen::VectorXd& force_mu, Eigen::MatrixXd* tangent, SvkElementScratch& scratch);

}  // namespace isospring::analysis::detail
