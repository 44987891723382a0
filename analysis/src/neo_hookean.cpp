// Compressible neo-Hookean (CalculiX's NEO HOOKE form): the stress and tangent at a point, the
// element force and tangent, and the assembly over the element colouring.
#include "isospring/analysis/neo_hookean.hpp"

#include <Eigen/Dense>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "assembly_structure.hpp"
#include "dense_products.hpp"
#include "isospring/analysis/elasticity.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::analysis {

NeoHookeanParameters neo_hookean_parameters(const Material& material, Formulation formulation) {
  if (formulation == Formulation::kPlaneStress)
    throw nurbs::InputError(
        "neo-Hookean material: plane stress is not supported (the thickness stretch would be an "
        "extra unknown per point); use plane strain or a 3D solid, or the St. Venant-Kirchhoff "
        "material");
  const double E = material.youngs_modulus, nu = material.poisson_ratio;
  if (!(E > 0) || !std::isfinite(E))
    throw nurbs::InputError("neo-Hookean material: Young's modulus " + std::to_string(E) +
                            " must be positive");
  if (!(nu > -1.0 && nu < 0.5))
    throw nurbs::InputError("neo-Hookean material: Poisson's ratio " + std::to_string(nu) +
                            " must lie in (-1, 0.5) (a compressible material)");
  return {E / (2.0 * (1.0 + nu)), E / (3.0 * (1.0 - 2.0 * nu))};
}

struct NeoHookeanAssembler::Impl {
  Impl(const Problem& problem, const DofMap& dofs)
      : structure(problem, dofs), dim(dofs.dofs_per_node()), thickness(thickness_factor(problem)) {}
  detail::AssemblyStructure structure;
  int dim;
  double thickness;
};

NeoHookeanAssembler::NeoHookeanAssembler(const Problem& problem, const DofMap& dofs) {
  if (problem.formulation == Formulation::kPlaneStress)
    neo_hookean_parameters(problem.material, problem.formulation);  // throws the explanation
  impl_ = std::make_unique<Impl>(problem, dofs);
  num_dofs_ = dofs.num_dofs();
}

NeoHookeanAssembler::~NeoHookeanAssembler() = default;

namespace {

using detail::product_transpose;

// The law at one point, in the Dim x Dim block of F (plane strain: F_33 = 1 enters through I1
// only, since H = F^-T is block diagonal with H_33 = 1). `valid` is false where J <= 0.
template <int Dim>
struct PointLaw {
  using Mat = Eigen::Matrix<double, Dim, Dim>;
  PointLaw(const Mat& F, const NeoHookeanParameters& m) : F(F), shear(m.shear), bulk(m.bulk) {
    J = F.determinant();
    valid = J > 0.0 && std::isfinite(J);
    if (!valid) return;
    H = F.inverse().transpose();
    I1 = F.squaredNorm() + (3 - Dim);
    a = std::pow(J, -2.0 / 3.0);
    P = shear * a * (F - (I1 / 3.0) * H) + bulk * J * (J - 1.0) * H;
  }
  /// The block A_i.k. (rows J, columns L) of dP_iJ / dF_kL.
  Mat block(int i, int k) const {
    const double s = shear * a;
    const double hh = s * 2.0 / 9.0 * I1 + bulk * J * (2.0 * J - 1.0);  // of H_iJ H_kL
    const double swap = s * I1 / 3.0 - bulk * J * (J - 1.0);            // of H_iL H_kJ
    Mat A = hh * H.row(i).transpose() * H.row(k) + swap * H.row(k).transpose() * H.row(i) -
            (2.0 / 3.0) * s * (F.row(i).transpose() * H.row(k) + H.row(i).transpose() * F.row(k));
    if (i == k) A += s * Mat::Identity();
    return A;
  }
  Mat F, H, P;
  double shear, bulk, J = 0, I1 = 0, a = 0;
  bool valid = false;
};

// Element force (n * Dim) and, when `tangent` is set, the element tangent. The tangent block of
// DOF components (i, k) is sum_q w G_q A_ik(q) G_q^T: formed as one matrix product over all
// points (columns of point q side by side), for the pairs i <= k (K_ki = K_ik^T by the major
// symmetry of A). Returns false where J <= 0.
template <int Dim>
bool element_neo_hookean(const detail::PatchQuadrature& quadrature, int patch, int element,
                         const int* element_nodes, const Eigen::VectorXd& u,
                         const NeoHookeanParameters& moduli, double thickness,
                         detail::QuadraturePoint& point, Eigen::VectorXd& force,
                         Eigen::MatrixXd* tangent) {
  using Mat = Eigen::Matrix<double, Dim, Dim>;
  const int n = quadrature.basis_count();
  const int nq = quadrature.points_per_element();
  constexpr int kPairs = Dim * (Dim + 1) / 2;
  thread_local Eigen::MatrixXd g, ue, all;
  thread_local std::array<Eigen::MatrixXd, kPairs> weighted;  // blocks w G A_ik
  g.resize(n, Dim);
  ue.resize(n, Dim);
  for (int a = 0; a < n; ++a)
    for (int c = 0; c < Dim; ++c) ue(a, c) = u[element_nodes[a] * Dim + c];
  force.setZero(n * Dim);
  if (tangent) {
    all.resize(n, nq * Dim);
    for (auto& m : weighted) m.resize(n, nq * Dim);
  }
  for (int q = 0; q < nq; ++q) {
    quadrature.evaluate(element, q, point);
    const double det = detail::physical_gradients(point, Dim, patch, element, g);
    const double w = point.weight * det * thickness;
    const Mat F = Mat::Identity() + ue.transpose().lazyProduct(g);
    const PointLaw<Dim> law(F, moduli);
    if (!law.valid) return false;
    // r_a,i = P_iJ G_a,J: row a of g P^T.
    const Eigen::Matrix<double, Eigen::Dynamic, Dim> r = g.lazyProduct(law.P.transpose());
    for (int a = 0; a < n; ++a)
      for (int i = 0; i < Dim; ++i) force[a * Dim + i] += w * r(a, i);
    if (!tangent) continue;
    all.middleCols(q * Dim, Dim) = g;
    int pair = 0;
    for (int i = 0; i < Dim; ++i)
      for (int k = i; k < Dim; ++k, ++pair)
        weighted[static_cast<size_t>(pair)].middleCols(q * Dim, Dim) =
            w * g.lazyProduct(law.block(i, k));
  }
  if (!tangent) return true;
  thread_local Eigen::MatrixXd kik;
  tangent->resize(n * Dim, n * Dim);
  int pair = 0;
  for (int i = 0; i < Dim; ++i)
    for (int k = i; k < Dim; ++k, ++pair) {
      product_transpose(weighted[static_cast<size_t>(pair)], all, kik);
      for (int b = 0; b < n; ++b)
        for (int a = 0; a < n; ++a) {
          (*tangent)(a * Dim + i, b * Dim + k) = kik(a, b);
          (*tangent)(b * Dim + k, a * Dim + i) = kik(a, b);
        }
    }
  return true;
}

}  // namespace

Eigen::VectorXd NeoHookeanAssembler::internal_force(const Eigen::VectorXd& u,
                                                    const NeoHookeanParameters& moduli,
                                                    Eigen::SparseMatrix<double>* tangent) const {
  const detail::AssemblyStructure& s = impl_->structure;
  const int dim = impl_->dim;
  if (u.size() != num_dofs_)
    throw std::invalid_argument("NeoHookeanAssembler: displacement of size " +
                                std::to_string(u.size()) + ", expected " +
                                std::to_string(num_dofs_));
  Eigen::VectorXd force = Eigen::VectorXd::Zero(num_dofs_);
  if (tangent) *tangent = s.empty_matrix();
  bool inverted = false;
  struct Scratch {
    detail::QuadraturePoint point;
    Eigen::VectorXd local;
    Eigen::MatrixXd local_tangent;
  };
  detail::for_each_element_by_colour<Scratch>(
      s, threads_, tangent && detail::heavy_elements(s), [&](int e, Scratch& scratch) {
        const auto& element = s.elements[static_cast<size_t>(e)];
        const auto& quadrature = s.quadratures[static_cast<size_t>(element.patch)];
        const int* nodes = s.nodes.data() + s.node_offset[static_cast<size_t>(e)];
        Eigen::MatrixXd* lt = tangent ? &scratch.local_tangent : nullptr;
        const bool ok =
            dim == 2
                ? element_neo_hookean<2>(quadrature, element.patch, element.index, nodes, u, moduli,
                                         impl_->thickness, scratch.point, scratch.local, lt)
                : element_neo_hookean<3>(quadrature, element.patch, element.index, nodes, u, moduli,
                                         impl_->thickness, scratch.point, scratch.local, lt);
        if (!ok) {
#pragma omp atomic write
          inverted = true;
          return;
        }
        const int n = quadrature.basis_count();
        for (int a = 0; a < n; ++a)
          for (int i = 0; i < dim; ++i) force[nodes[a] * dim + i] += scratch.local[a * dim + i];
        if (tangent) s.scatter(e, scratch.local_tangent, *tangent);
      });
  if (inverted) force.setConstant(std::numeric_limits<double>::quiet_NaN());
  return force;
}

}  // namespace isospring::analysis
