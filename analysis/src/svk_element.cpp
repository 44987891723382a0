// The St. Venant-Kirchhoff element kernel: force and tangent from the element's basis gradients.
#include "svk_element.hpp"

#include <Eigen/Dense>

#include "assembly_structure.hpp"

namespace isospring::analysis::detail {

void element_gradients(const PatchQuadrature& quadrature, int patch, int element, int dim,
                       double thickness, QuadraturePoint& point, ElementGradients& out) {
  const int n = quadrature.basis_count();
  const int nq = quadrature.points_per_element();
  out.gradients.resize(n, dim * nq);
  out.weights.resize(nq);
  thread_local Eigen::MatrixXd g;
  g.resize(n, dim);
  for (int q = 0; q < nq; ++q) {
    quadrature.evaluate(element, q, point);
    const double det = physical_gradients(point, dim, patch, element, g);
    out.weights[q] = point.weight * det * thickness;
    out.gradients.middleCols(q * dim, dim) = g;
  }
}

namespace {

// Deformation gradient F = I + u^T G_q and second Piola-Kirchhoff stress S of unit lambda and
// unit mu at every point (Dim x Dim blocks side by side), and the element forces
// r_a = sum_q w P G_a with P = F S.
template <int Dim>
void forces_and_states(const ElementGradients& element, const Eigen::MatrixXd& displacements,
                       const LameParameters& lame, Eigen::VectorXd& force_lambda,
                       Eigen::VectorXd& force_mu, SvkElementScratch& scratch) {
  using Mat = Eigen::Matrix<double, Dim, Dim>;
  const Eigen::MatrixXd& gradients = element.gradients;
  const Eigen::Index n = gradients.rows();
  const Eigen::Index nq = element.weights.size();
  scratch.deformation.resize(Dim, Dim * nq);
  scratch.stress.resize(Dim, Dim * nq);
  // Forces as n x Dim (row a = r_a), accumulated point by point.
  Eigen::Matrix<double, Eigen::Dynamic, Dim> rl =
      Eigen::Matrix<double, Eigen::Dynamic, Dim>::Zero(n, Dim);
  Eigen::Matrix<double, Eigen::Dynamic, Dim> rm =
      Eigen::Matrix<double, Eigen::Dynamic, Dim>::Zero(n, Dim);
  for (Eigen::Index q = 0; q < nq; ++q) {
    const auto g = gradients.template middleCols<Dim>(q * Dim);
    const double w = element.weights[q];
    const Mat F = Mat::Identity() + displacements.transpose().lazyProduct(g);
    const Mat E = 0.5 * (F.transpose() * F - Mat::Identity());
    rl.noalias() += g.lazyProduct((w * E.trace() * F).transpose());
    rm.noalias() += g.lazyProduct((2.0 * w * F * E).transpose());
    scratch.deformation.middleCols(q * Dim, Dim) = F;
    scratch.stress.middleCols(q * Dim, Dim) =
        lame.lambda * E.trace() * Mat::Identity() + 2.0 * lame.mu * E;
  }
  force_lambda.resize(n * Dim);
  force_mu.resize(n * Dim);
  Eigen::Map<Eigen::Matrix<double, Dim, Eigen::Dynamic>>(force_lambda.data(), Dim, n) =
      rl.transpose();
  Eigen::Map<Eigen::Matrix<double, Dim, Eigen::Dynamic>>(force_mu.data(), Dim, n) = rm.transpose();
}

// Rows [row, row + n) of `out` = [G_q T_ik(q)]_q with T_ik = w (lambda f_i f_k^T + mu f_k f_i^T +
// mu (F F^T)_ik I + delta_ik S).
template <int Dim>
void weighted_gradients(const ElementGradients& element, const LameParameters& lame, int i, int k,
                        const SvkElementScratch& scratch, Eigen::MatrixXd& out, Eigen::Index row) {
  using Mat = Eigen::Matrix<double, Dim, Dim>;
  using Vec = Eigen::Matrix<double, Dim, 1>;
  const Eigen::Index n = element.gradients.rows();
  const Eigen::Index nq = element.weights.size();
  for (Eigen::Index q = 0; q < nq; ++q) {
    const Mat F = scratch.deformation.template middleCols<Dim>(q * Dim);
    const Vec fi = F.row(i).transpose();
    const Vec fk = F.row(k).transpose();
    Mat t = lame.lambda * fi * fk.transpose() + lame.mu * fk * fi.transpose();
    t.diagonal().array() += lame.mu * fi.dot(fk);
    if (i == k) t += scratch.stress.template middleCols<Dim>(q * Dim);
    t *= element.weights[q];
    out.template middleCols<Dim>(q * Dim).middleRows(row, n).noalias() =
        element.gradients.template middleCols<Dim>(q * Dim).lazyProduct(t);
  }
}

}  // namespace

template <int Dim>
void svk_element(const ElementGradients& element, const Eigen::MatrixXd& displacements,
                 const LameParameters& lame, Eigen::VectorXd& force_lambda,
                 Eigen::VectorXd& force_mu, Eigen::MatrixXd* tangent, SvkElementScratch& scratch) {
  forces_and_states<Dim>(element, displacements, lame, force_lambda, force_mu, scratch);
  if (!tangent) return;
  const Eigen::MatrixXd& gradients = element.gradients;
  const Eigen::Index n = gradients.rows();
  // The diagonal blocks (i, i) as lower triangles; the off-diagonal ones (i < k) whole, from one
  // product of their weighted gradients stacked (G is packed once for all of them); block (k, i)
  // is the transpose of block (i, k). The caller runs this with nthreads-var 1 (SvkAssembler's
  // element loop): Eigen would otherwise start its own OpenMP team for products of this size
  // when the element loop runs serially.
  constexpr int kOffDiagonal = Dim * (Dim - 1) / 2;
  const Eigen::Index columns = gradients.cols();
  scratch.weighted.resize(n, columns);
  for (int i = 0; i < Dim; ++i) {
    weighted_gradients<Dim>(element, lame, i, i, scratch, scratch.weighted, 0);
    Eigen::MatrixXd& ii = scratch.diagonal[static_cast<size_t>(i)];
    ii.resize(n, n);
    ii.triangularView<Eigen::Lower>() = scratch.weighted * gradients.transpose();
  }
  scratch.stacked.resize(kOffDiagonal * n, columns);
  for (int i = 0, pair = 0; i < Dim; ++i)
    for (int k = i + 1; k < Dim; ++k, ++pair)
      weighted_gradients<Dim>(element, lame, i, k, scratch, scratch.stacked, pair * n);
  scratch.off_diagonal.resize(kOffDiagonal * n, n);
  scratch.off_diagonal.noalias() = scratch.stacked * gradients.transpose();
  // K_(a,i),(b,k) = block(i, k)(a, b) = K_(b,k),(a,i): block (i, k) is the strided view of the
  // tangent at rows i, i + Dim, ... and columns k, k + Dim, ....
  const Eigen::Index size = n * Dim;
  tangent->resize(size, size);
  using Strided = Eigen::Map<Eigen::MatrixXd, 0, Eigen::Stride<Eigen::Dynamic, Eigen::Dynamic>>;
  const Eigen::Stride<Eigen::Dynamic, Eigen::Dynamic> stride(Dim * size, Dim);
  for (int i = 0; i < Dim; ++i) {
    Strided view(tangent->data() + i + i * size, n, n, stride);
    view.triangularView<Eigen::Lower>() = scratch.diagonal[static_cast<size_t>(i)];
    view.triangularView<Eigen::StrictlyUpper>() =
        scratch.diagonal[static_cast<size_t>(i)].transpose();
  }
  for (int i = 0, pair = 0; i < Dim; ++i)
    for (int k = i + 1; k < Dim; ++k, ++pair) {
      const auto block = scratch.off_diagonal.middleRows(pair * n, n);
      Strided(tangent->data() + i + k * size, n, n, stride) = block;
      Strided(tangent->data() + k + i * size, n, n, stride) = block.transpose();
    }
}

template void svk_element<2>(const ElementGradients&, const Eigen::MatrixXd&, const LameParameters&,
                             Eigen::VectorXd&, Eigen::VectorXd&, Eigen::MatrixXd*,
                             SvkElementScratch&);
template void svk_element<3>(const ElementGradients&, const Eigen::MatrixXd&, const LameParameters&,
                             Eigen::VectorXd&, Eigen::VectorXd&, Eigen::MatrixXd*,
                             SvkElementScratch&);

}  // namespace isospring::analysis::detail
