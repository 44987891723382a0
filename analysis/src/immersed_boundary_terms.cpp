// Supports by the symmetric Nitsche method with a per-cell penalty from a generalised eigenvalue
// problem, and tractions/pressures on the part's faces.
#include <Eigen/Dense>
#include <algorithm>
#include <map>
#include <sstream>

#include "immersed_kernels.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/nurbs/quadrature.hpp"

namespace isospring::analysis::detail {

namespace {

// Which load or support acts at a boundary point.
struct FaceTerm {
  size_t point;
  const ImmersedSupport* support = nullptr;  // else a load with this traction
  Eigen::Vector3d traction = Eigen::Vector3d::Zero();
};

// The element a boundary point belongs to: a point on a grid line is nudged into the part (along
// -n), so that it is taken from the cell that holds the part there.
Element element_of_boundary_point(const ImmersedContext& context,
                                  const geometry::BoundaryPoint& b) {
  const auto& basis = context.basis;
  double h = 1e300;
  for (int d = 0; d < basis.dim(); ++d)
    h = std::min(h, context.domain->extent[d] / basis.elements(d));
  const Element e = basis.element_of(b.point - 1e-9 * h * b.normal);
  if (context.cell_of_element[static_cast<size_t>(basis.flat(e))] < 0) {
    std::ostringstream message;
    message << "immersed domain: the boundary point (" << b.point.transpose() << ") of face "
            << b.face << " lies in no cell of the part; the domain's boundary and cells disagree";
    throw nurbs::InputError(message.str());
  }
  return e;
}

std::map<int, std::vector<FaceTerm>> terms_by_element(const ImmersedContext& context) {
  const auto& domain = *context.domain;
  const auto& options = *context.options;
  std::map<int, std::vector<FaceTerm>> out;
  for (size_t i = 0; i < domain.boundary.size(); ++i) {
    const auto& b = domain.boundary[i];
    std::vector<FaceTerm> terms;
    for (const auto& s : options.supports)
      if (s.face == b.face) terms.push_back({i, &s, Eigen::Vector3d::Zero()});
    Eigen::Vector3d traction = Eigen::Vector3d::Zero();
    bool loaded = false;
    for (const auto& t : options.tractions)
      if (t.face == b.face) {
        traction += t.function ? t.function(b.point, b.normal) : t.value;
        loaded = true;
      }
    for (const auto& p : options.pressures)
      if (p.face == b.face) {
        traction -= p.value * b.normal;
        loaded = true;
      }
    if (loaded) terms.push_back({i, nullptr, traction});
    if (terms.empty()) continue;
    const int e = context.basis.flat(element_of_boundary_point(context, b));
    auto& list = out[e];
    list.insert(list.end(), terms.begin(), terms.end());
  }
  return out;
}

// Projector on the held components.
Eigen::MatrixXd held(const ImmersedSupport& s, const Eigen::Vector3d& n, int dim) {
  if (s.symmetry) return n.head(dim) * n.head(dim).transpose();
  Eigen::MatrixXd P = Eigen::MatrixXd::Zero(dim, dim);
  for (int c = 0; c < dim; ++c) P(c, c) = s.fixed[static_cast<size_t>(c)] ? 1.0 : 0.0;
  return P;
}

// Stiffness of the element's basis over the whole cell (Gauss, p + 1 points per direction).
Eigen::MatrixXd full_cell_stiffness(const ImmersedContext& context, const Element& e) {
  const auto& basis = context.basis;
  const int dim = basis.dim();
  const Eigen::Vector3d lo = basis.element_lo(e), hi = basis.element_hi(e);
  int points = 1;
  for (int d = 0; d < dim; ++d) points = std::max(points, basis.degree(d) + 1);
  const nurbs::GaussRule g = nurbs::gauss_legendre(points);
  const int n = static_cast<int>(g.points.size());
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(basis.count() * dim, basis.count() * dim);
  BasisAt at;
  for (int k = 0; k < (dim == 3 ? n : 1); ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const std::array<int, 3> q{i, j, k};
        Eigen::Vector3d x = lo;
        double w = context.thickness;
        for (int d = 0; d < dim; ++d) {
          const size_t m = static_cast<size_t>(q[static_cast<size_t>(d)]);
          x[d] = 0.5 * (lo[d] + hi[d]) + 0.5 * (hi[d] - lo[d]) * g.points[m];
          w *= 0.5 * (hi[d] - lo[d]) * g.weights[m];
        }
        basis.evaluate(e, x, at);
        const Eigen::MatrixXd B = strain_operator(at.gradients, dim);
        A.noalias() += w * B.transpose() * context.elasticity * B;
      }
  return A;
}

// Largest lambda with v^T boundary v = lambda v^T A v on the complement of A's null space (the
// rigid motions, where both forms vanish).
double largest_generalised_eigenvalue(const Eigen::MatrixXd& A, const Eigen::MatrixXd& boundary) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(A);
  const double cut = 1e-10 * eigen.eigenvalues().maxCoeff();
  std::vector<Eigen::Index> range;
  for (Eigen::Index k = 0; k < A.rows(); ++k)
    if (eigen.eigenvalues()[k] > cut) range.push_back(k);
  Eigen::MatrixXd Z(A.rows(), static_cast<Eigen::Index>(range.size()));
  for (size_t k = 0; k < range.size(); ++k)
    Z.col(static_cast<Eigen::Index>(k)) =
        eigen.eigenvectors().col(range[k]) / std::sqrt(eigen.eigenvalues()[range[k]]);
  const Eigen::MatrixXd M = Z.transpose() * boundary * Z;
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(M, Eigen::EigenvaluesOnly)
      .eigenvalues()
      .maxCoeff();
}

}  // namespace

double add_face_terms(const ImmersedContext& context, ImmersedScatter& scatter) {
  const auto& domain = *context.domain;
  const int dim = domain.dimension;
  const double modulus = context.lame.lambda + 2 * context.lame.mu;
  double max_penalty = 0;
  BasisAt at;
  for (const auto& [flat, terms] : terms_by_element(context)) {
    const int cell = context.cell_of_element[static_cast<size_t>(flat)];
    const Element& e = context.cell_elements[static_cast<size_t>(cell)];
    const int n = context.basis.count() * dim;
    // Per point: values operator N and traction operator T = (sigma n) of the basis.
    struct PointOperators {
      Eigen::MatrixXd N, T, P;
      double w;
    };
    std::vector<PointOperators> supported;
    Eigen::VectorXd f = Eigen::VectorXd::Zero(n);
    Eigen::MatrixXd boundary = Eigen::MatrixXd::Zero(n, n);
    for (const FaceTerm& term : terms) {
      const auto& b = domain.boundary[term.point];
      context.basis.evaluate(e, b.point, at);
      const double w = b.weight * context.thickness;
      const Eigen::MatrixXd N = value_operator(at.values, dim);
      if (!term.support) {
        const Eigen::VectorXd traction = term.traction.head(dim);
        f.noalias() += w * N.transpose() * traction;
        continue;
      }
      const Eigen::MatrixXd T =
          normal_operator(b.normal, dim) * context.elasticity * strain_operator(at.gradients, dim);
      const Eigen::MatrixXd P = held(*term.support, b.normal, dim);
      boundary.noalias() += w * T.transpose() * P * T;
      supported.push_back({N, T, P, w});
    }
    Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n, n);
    if (!supported.empty()) {
      const double beta = context.options->nitsche_factor *
                          largest_generalised_eigenvalue(full_cell_stiffness(context, e), boundary);
      const Eigen::Vector3d size = context.basis.element_hi(e) - context.basis.element_lo(e);
      double h = size[0];
      for (int d = 1; d < dim; ++d) h = std::min(h, size[d]);
      max_penalty = std::max(max_penalty, beta * h / modulus);
      size_t k = 0;
      for (const FaceTerm& term : terms) {
        if (!term.support) continue;
        const auto& [N, T, P, w] = supported[k++];
        const auto& b = domain.boundary[term.point];
        const ImmersedSupport& s = *term.support;
        Eigen::Vector3d g = s.value;
        if (s.symmetry)
          g.setZero();
        else if (s.value_function)
          g = s.value_function(b.point);
        const Eigen::MatrixXd PT = P * T, PN = P * N;
        K.noalias() += w * (beta * N.transpose() * PN - N.transpose() * PT - PT.transpose() * N);
        const Eigen::VectorXd held_value = g.head(dim);
        f.noalias() += w * (beta * PN.transpose() - PT.transpose()) * held_value;
      }
    }
    scatter.add_matrix(at.control_points, K);
    scatter.add_vector(at.control_points, f);
  }
  return max_penalty;
}

}  // namespace isospring::analysis::detail
