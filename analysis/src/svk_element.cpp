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
    const auto g = gradients.middleCols(q * Dim, Dim);
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

// scratch.weighted = [G_q T_ik(q)]_q with T_ik = w (lambda f_i f_k^T + mu f_k f_i^T +
// mu (F F^T)_ik I + delta_ik S).
template <int Dim>
void weighted_gradients(const ElementGradients& element, const LameParameters& lame, int i, int k,
                        SvkElementScratch& scratch) {
  using Mat = Eigen::Matrix<double, Dim, Dim>;
  using Vec = Eigen::Matrix<double, Dim, 1>;
  const Eigen::Index nq = element.weights.size();
  scratch.weighted.resize(element.gradients.rows(), Dim * nq);
  for (Eigen::Index q = 0; q < nq; ++q) {
    const Mat F = scratch.deformation.template middleCols<Dim>(q * Dim);
    const Vec fi = F.row(i).transpose();
    const Vec fk = F.row(k).transpose();
    Mat t = lame.lambda * fi * fk.transpose() + lame.mu * fk * fi.transpose();
    t.diagonal().array() += lame.mu * fi.dot(fk);
    if (i == k) t += scratch.stress.template middleCols<Dim>(q * Dim);
    t *= element.weights[q];
    scratch.weighted.middleCols(q * Dim, Dim).noalias() =
        element.gradients.middleCols(q * Dim, Dim).lazyProduct(t);
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
  // Blocks (i, k) with i <= k: the diagonal ones as lower triangles, the others whole (block
  // (k, i) is their transpose). The caller runs this with nthreads-var 1 (SvkAssembler's element
  // loop): Eigen would otherwise start its own OpenMP team for products of this size when the
  // element loop runs serially.
  for (int i = 0; i < Dim; ++i)
    for (int k = i; k < Dim; ++k) {
      weighted_gradients<Dim>(element, lame, i, k, scratch);
      Eigen::MatrixXd& ik = scratch.blocks[static_cast<size_t>(i * Dim + k)];
      ik.resize(n, n);
      if (i == k)
        ik.triangularView<Eigen::Lower>() = scratch.weighted * gradients.transpose();
      else
        ik.noalias() = scratch.weighted * gradients.transpose();
    }
  // K_(a,i),(b,k) = block(i, k)(a, b) = K_(b,k),(a,i): the diagonal blocks' lower triangles
  // fill both of their triangles, the others their own and the mirrored block.
  tangent->resize(n * Dim, n * Dim);
  for (int i = 0; i < Dim; ++i)
    for (int k = i; k < Dim; ++k) {
      const Eigen::MatrixXd& block = scratch.blocks[static_cast<size_t>(i * Dim + k)];
      for (Eigen::Index b = 0; b < n; ++b)
        for (Eigen::Index a = i == k ? b : 0; a < n; ++a) {
          const double v = block(a, b);
          (*tangent)(a * Dim + i, b * Dim + k) = v;
          (*tangent)(b * Dim + k, a * Dim + i) = v;
        }
    }
}

template void svk_element<2>(const ElementGradients&, const Eigen::MatrixXd&, const LameParameters&,
                             Eigen::VectorXd&, Eigen::VectorXd&, Eigen::MatrixXd*,
                             SvkElementScratch&);
template void svk_element<3>(const ElementGradients&, const Eigen::MatrixXd&, const LameParameters&,
                             Eigen::VectorXd&, Eigen::VectorXd&, Eigen::MatrixXd*,
                             SvkElementScratch&);

}  // namespace isospring::analysis::detail
