// Lame-split stiffness matrices with spatial weights: per element, the basis gradients at all
// quadrature points side by side, and every block a dense product (as ElementStiffness).
#include "isospring/analysis/lame_stiffness.hpp"

#include <array>
#include <vector>

#include "assembly_structure.hpp"
#include "bbar_lame_parts.hpp"
#include "dense_products.hpp"
#include "isospring/analysis/elasticity.hpp"
#include "volumetric_projection.hpp"

namespace isospring::analysis {

std::vector<LameStiffness> assemble_lame_stiffness(const Problem& problem, const DofMap& dofs,
                                                   const std::vector<SpatialWeight>& weights,
                                                   int threads) {
  detail::check_volumetric(problem);  // before the assembly: B-bar in plane stress is an error
  const detail::AssemblyStructure structure(problem, dofs);
  const int dim = structure.dofs_per_node;
  const double thickness = thickness_factor(problem);
  const size_t nw = weights.size();
  // Local matrices 2k (lambda part) and 2k + 1 (mu part) for weight k.
  const std::vector<Eigen::SparseMatrix<double>> upper = detail::assemble_matrices(
      structure, 2 * nw,
      [&](int e, detail::QuadraturePoint& point, std::vector<Eigen::MatrixXd>& locals) {
        thread_local Eigen::MatrixXd g, trace;
        thread_local std::array<Eigen::MatrixXd, 3> grad, weighted;
        thread_local std::array<std::array<Eigen::MatrixXd, 3>, 3> products;
        thread_local std::vector<double> factor;
        const auto& element = structure.elements[static_cast<size_t>(e)];
        const auto& quadrature = structure.quadratures[static_cast<size_t>(element.patch)];
        const int n = quadrature.basis_count();
        const int nq = quadrature.points_per_element();
        g.resize(n, dim);
        for (int i = 0; i < dim; ++i) grad[static_cast<size_t>(i)].resize(n, nq);
        factor.assign(static_cast<size_t>(nq) * nw, 0.0);
        for (int q = 0; q < nq; ++q) {
          quadrature.evaluate(element.index, q, point);
          const double det =
              detail::physical_gradients(point, dim, element.patch, element.index, g);
          for (int i = 0; i < dim; ++i) grad[static_cast<size_t>(i)].col(q) = g.col(i);
          for (size_t k = 0; k < nw; ++k)
            factor[k * static_cast<size_t>(nq) + static_cast<size_t>(q)] =
                point.weight * det * thickness * (weights[k] ? weights[k](point.point) : 1.0);
        }
        for (size_t k = 0; k < nw; ++k) {
          const Eigen::Map<const Eigen::VectorXd> w(factor.data() + k * static_cast<size_t>(nq),
                                                    nq);
          for (int i = 0; i < dim; ++i)
            weighted[static_cast<size_t>(i)] = grad[static_cast<size_t>(i)] * w.asDiagonal();
          // products[i][j] = weighted_i grad_j^T: the lambda part's block (i, j) and, with the
          // component pair transposed, the mu part's block (j, i).
          for (int i = 0; i < dim; ++i)
            for (int j = 0; j < dim; ++j)
              detail::product_transpose(weighted[static_cast<size_t>(i)],
                                        grad[static_cast<size_t>(j)],
                                        products[static_cast<size_t>(i)][static_cast<size_t>(j)]);
          trace.setZero(n, n);
          for (int i = 0; i < dim; ++i)
            trace += products[static_cast<size_t>(i)][static_cast<size_t>(i)];
          Eigen::MatrixXd& local_lambda = locals[2 * k];
          Eigen::MatrixXd& local_mu = locals[2 * k + 1];
          local_lambda.resize(n * dim, n * dim);
          local_mu.resize(n * dim, n * dim);
          for (int i = 0; i < dim; ++i)
            for (int j = 0; j < dim; ++j) {
              const Eigen::MatrixXd& lambda_block =
                  products[static_cast<size_t>(i)][static_cast<size_t>(j)];
              const Eigen::MatrixXd& mu_block =
                  products[static_cast<size_t>(j)][static_cast<size_t>(i)];
              for (int b = 0; b < n; ++b)
                for (int a = 0; a < n; ++a) {
                  local_lambda(a * dim + i, b * dim + j) = lambda_block(a, b);
                  local_mu(a * dim + i, b * dim + j) =
                      mu_block(a, b) + (i == j ? trace(a, b) : 0.0);
                }
            }
        }
      },
      threads);
  std::vector<LameStiffness> out(nw);
  for (size_t k = 0; k < nw; ++k) {
    out[k].lambda_part = upper[2 * k].selfadjointView<Eigen::Upper>();
    out[k].mu_part = upper[2 * k + 1].selfadjointView<Eigen::Upper>();
  }
  // B-bar: the displacement parts above turned into the projected ones (bbar_lame_parts.hpp).
  if (problem.volumetric == Volumetric::kBbar) {
    const std::vector<Eigen::SparseMatrix<double>> volumetric =
        detail::bbar_weighted_volumetric(problem, dofs, structure, weights);
    for (size_t k = 0; k < nw; ++k) detail::make_bbar_lame_parts(volumetric[k], out[k]);
  }
  return out;
}

}  // namespace isospring::analysis
