// Stiffness and consistent mass matrices.
#include <Eigen/Dense>
#include <array>

#include "assembly_structure.hpp"
#include "dense_products.hpp"
#include "element_classes.hpp"
#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/elasticity.hpp"
#include "volumetric_projection.hpp"

namespace isospring::analysis {

namespace detail {

ElementStiffness::ElementStiffness(const Problem& problem, const AssemblyStructure& structure,
                                   bool reuse_equal_elements)
    : structure_(&structure), dim_(structure.dofs_per_node) {
  const LameParameters lame = lame_parameters(problem.material, problem.formulation);
  lambda_ = kernel_lambda(problem, lame.lambda, lame.mu);  // B-bar: deviatoric part only
  mu_ = lame.mu;
  thickness_ = thickness_factor(problem);
  // Cache the matrices of affine patches whose elements fall into few classes (at most one in
  // eight elements distinct: otherwise the cache saves little and costs memory).
  element_class_.resize(structure.quadratures.size());
  class_matrix_.resize(structure.quadratures.size());
  if (!reuse_equal_elements) return;
  std::vector<int> patch_start(structure.quadratures.size() + 1, 0);
  for (size_t p = 0; p < structure.quadratures.size(); ++p)
    patch_start[p + 1] = patch_start[p] + structure.quadratures[p].num_elements();
  for (size_t p = 0; p < structure.quadratures.size(); ++p) {
    const int elements = structure.quadratures[p].num_elements();
    if (elements < 16) continue;
    ElementClasses classes = affine_element_classes(structure.quadratures[p]);
    if (classes.of_element.empty() || classes.first.size() * 8 > static_cast<size_t>(elements))
      continue;
    // structure.elements lists the patches' elements in order, so patch p's element k is
    // patch_start[p] + k there.
    QuadraturePoint point;
    class_matrix_[p].resize(classes.first.size());
    for (size_t c = 0; c < classes.first.size(); ++c)
      integrate(patch_start[p] + classes.first[c], point, class_matrix_[p][c]);
    element_class_[p] = std::move(classes.of_element);
    cached_elements_ += elements;
  }
}

void ElementStiffness::operator()(int e, QuadraturePoint& point, Eigen::MatrixXd& local) const {
  const auto& element = structure_->elements[static_cast<size_t>(e)];
  const auto& classes = element_class_[static_cast<size_t>(element.patch)];
  if (classes.empty()) {
    integrate(e, point, local);
    return;
  }
  local = class_matrix_[static_cast<size_t>(element.patch)]
                       [static_cast<size_t>(classes[static_cast<size_t>(element.index)])];
}

void ElementStiffness::integrate(int e, QuadraturePoint& point, Eigen::MatrixXd& local) const {
  const int dim = dim_;
  const auto& element = structure_->elements[static_cast<size_t>(e)];
  const auto& quadrature = structure_->quadratures[static_cast<size_t>(element.patch)];
  const int n = quadrature.basis_count();
  const int nq = quadrature.points_per_element();
  // Columns of all quadrature points side by side: gradients[c] is n x nq (dR/dx_c), and
  // weighted[c] the same times w det J. Then int dR_a/dx_i dR_b/dx_j = weighted[i] grad[j]^T
  // is one matrix product per component pair.
  thread_local std::array<Eigen::MatrixXd, 3> gradients, weighted;
  thread_local Eigen::MatrixXd g;
  for (int c = 0; c < dim; ++c) {
    gradients[static_cast<size_t>(c)].resize(n, nq);
    weighted[static_cast<size_t>(c)].resize(n, nq);
  }
  g.resize(n, dim);
  for (int q = 0; q < nq; ++q) {
    quadrature.evaluate(element.index, q, point);
    const double det = detail::physical_gradients(point, dim, element.patch, element.index, g);
    const double w = point.weight * det * thickness_;
    for (int c = 0; c < dim; ++c) {
      gradients[static_cast<size_t>(c)].col(q) = g.col(c);
      weighted[static_cast<size_t>(c)].col(q) = w * g.col(c);
    }
  }
  // sigma = lambda tr(eps) I + 2 mu eps gives the block (i, j) of the pair (a, b):
  // lambda M_ij + mu M_ji + mu delta_ij sum_k M_kk with M_ij = int dR_a/dx_i dR_b/dx_j.
  // Chunked GEMMs (product_transpose): never Eigen's own OpenMP team, which would oversubscribe
  // a loaded machine when this loop runs serially, and 2.9x faster than the lazyProduct used
  // before (bench_identify_model, BM_StiffnessAssembly, degree 3 in 3D: 426 -> 145 ms on one
  // thread). The diagonal products serve both the trace and the blocks (i, i).
  thread_local Eigen::MatrixXd m, trace_sum;
  thread_local std::array<Eigen::MatrixXd, 3> diagonal;
  trace_sum.setZero(n, n);
  for (int c = 0; c < dim; ++c) {
    detail::product_transpose(weighted[static_cast<size_t>(c)], gradients[static_cast<size_t>(c)],
                              diagonal[static_cast<size_t>(c)]);
    trace_sum += diagonal[static_cast<size_t>(c)];
  }
  local.resize(n * dim, n * dim);
  for (int i = 0; i < dim; ++i)
    for (int j = i; j < dim; ++j) {
      if (i != j)
        detail::product_transpose(weighted[static_cast<size_t>(i)],
                                  gradients[static_cast<size_t>(j)], m);
      const Eigen::MatrixXd& mij = i == j ? diagonal[static_cast<size_t>(i)] : m;
      for (int b = 0; b < n; ++b)
        for (int a = 0; a < n; ++a) {
          double v = lambda_ * mij(a, b) + mu_ * mij(b, a);
          if (i == j) v += mu_ * trace_sum(a, b);
          local(a * dim + i, b * dim + j) = v;
          local(b * dim + j, a * dim + i) = v;
        }
    }
}

}  // namespace detail

Eigen::SparseMatrix<double> assemble_stiffness(const Problem& problem, const DofMap& dofs) {
  const detail::AssemblyStructure structure(problem, dofs);
  Eigen::SparseMatrix<double> k =
      detail::assemble_matrix(structure, detail::ElementStiffness(problem, structure));
  if (problem.volumetric == Volumetric::kBbar)
    k += detail::bbar_volumetric_stiffness(problem, dofs, structure);
  return k;
}

Eigen::SparseMatrix<double> assemble_consistent_mass(const Problem& problem, const DofMap& dofs) {
  const detail::AssemblyStructure structure(problem, dofs);
  const int dim = dofs.dofs_per_node();
  const double factor = problem.material.density * thickness_factor(problem);
  return detail::assemble_matrix(structure, [&](int e, detail::QuadraturePoint& point,
                                                Eigen::MatrixXd& local) {
    const auto& element = structure.elements[static_cast<size_t>(e)];
    const auto& quadrature = structure.quadratures[static_cast<size_t>(element.patch)];
    const int n = quadrature.basis_count();
    thread_local Eigen::MatrixXd g, scalar;
    g.resize(n, dim);
    scalar.setZero(n, n);
    for (int q = 0; q < quadrature.points_per_element(); ++q) {
      quadrature.evaluate(element.index, q, point);
      const double det = detail::physical_gradients(point, dim, element.patch, element.index, g);
      scalar.noalias() += (point.weight * det * factor) * point.values * point.values.transpose();
    }
    local.setZero(n * dim, n * dim);
    for (int b = 0; b < n; ++b)
      for (int a = 0; a < n; ++a)
        for (int c = 0; c < dim; ++c) local(a * dim + c, b * dim + c) = scalar(a, b);
  });
}

}  // namespace isospring::analysis
