// Supports by the symmetric Nitsche method with a per-cell penalty from a generalised eigenvalue
// problem, and tractions/pressures on the part's faces.
#include <Eigen/Dense>
#include <algorithm>
#include <map>
#include <sstream>

#include "immersed_bbar.hpp"
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
    // On a face that is also supported, the held components' traction is Nitsche's (sigma n
    // itself); a traction acts on the free components only: (I - P) t.
    Eigen::Matrix3d free = Eigen::Matrix3d::Identity();
    for (const auto& s : options.supports)
      if (s.face == b.face) {
        if (s.symmetry) free -= b.normal * b.normal.transpose();
        for (int c = 0; c < 3; ++c)
          if (!s.symmetry && s.fixed[static_cast<size_t>(c)]) free(c, c) = 0.0;
      }
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
    if (loaded) terms.push_back({i, nullptr, free * traction});
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

// The stabilised energy of the 3^d block of active cells around a cut element e: the bulk stiffness
// of their parts plus the ghost penalty on the faces between them, over the union of their control
// points (`cps`). Why a block and not the cell alone: a cell with a sliver of the part has almost
// no energy of its own; the ghost penalty passes control in from its neighbours (diagonal ones too,
// for a corner sliver whose direct neighbours are slivers as well). A cell the part fills has its
// full energy: its block is the cell itself (3^d times smaller eigenproblems; in 3D that is most of
// the assembly time otherwise).
Eigen::MatrixXd block_energy(const ImmersedContext& context, const Element& e,
                             std::vector<int>& cps) {
  const auto& basis = context.basis;
  const int dim = basis.dim();
  const int cell = context.cell_of_element[static_cast<size_t>(basis.flat(e))];
  const bool whole =
      context.domain->cells[static_cast<size_t>(cell)].kind == geometry::CellKind::kInside;
  const int reach = whole ? 0 : 1;
  std::vector<Element> block;
  for (int k = (dim == 3 ? -reach : 0); k <= (dim == 3 ? reach : 0); ++k)
    for (int j = -reach; j <= reach; ++j)
      for (int i = -reach; i <= reach; ++i) {
        const Element o{e[0] + i, e[1] + j, e[2] + k};
        bool inside = true;
        for (int d = 0; d < 3; ++d)
          inside = inside && o[static_cast<size_t>(d)] >= 0 &&
                   o[static_cast<size_t>(d)] < basis.elements(d);
        if (inside && context.cell_of_element[static_cast<size_t>(basis.flat(o))] >= 0)
          block.push_back(o);
      }
  std::map<int, int> place;
  cps.clear();
  const auto index_of = [&](int cp) {
    const auto [it, added] = place.emplace(cp, static_cast<int>(cps.size()));
    if (added) cps.push_back(cp);
    return it->second;
  };
  std::vector<int> local_cps;
  for (const Element& o : block) {
    basis.control_points(o, local_cps);
    for (int cp : local_cps) index_of(cp);
  }
  const Eigen::Index n = static_cast<Eigen::Index>(cps.size()) * dim;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, n);
  const auto add = [&](const std::vector<int>& at, const Eigen::MatrixXd& local) {
    for (size_t b = 0; b < at.size(); ++b)
      for (size_t a = 0; a < at.size(); ++a)
        A.block(place[at[a]] * dim, place[at[b]] * dim, dim, dim) += local.block(
            static_cast<Eigen::Index>(a) * dim, static_cast<Eigen::Index>(b) * dim, dim, dim);
  };
  Eigen::MatrixXd local;
  for (const Element& o : block) {
    cell_stiffness(context,
                   static_cast<size_t>(context.cell_of_element[static_cast<size_t>(basis.flat(o))]),
                   local_cps, local);
    add(local_cps, local);
  }
  if (context.options->ghost_penalty > 0)
    for (const Element& o : block)
      for (int d = 0; d < dim; ++d) {
        Element up = o;
        ++up[static_cast<size_t>(d)];
        const bool in_block = std::find(block.begin(), block.end(), up) != block.end();
        const std::pair<int, int> face{basis.flat(o), d};
        if (in_block && context.ghost.count(face)) {
          ghost_face_matrix(context, face, local_cps, local);
          add(local_cps, local);
        }
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

// The boundary form involves the cell's basis only, so the eigenvalue problem reduces to it: the
// block energy minimised over the block's other DOFs for given cell DOFs is the Schur complement
// S = A_cc - A_co A_oo^-1 A_oc (max v^T B v / v^T A v = max w^T B w / w^T S w). A_oo is shifted
// by 1e-12 of its largest diagonal: a DOF without energy in the block has no coupling either, so
// the shift changes nothing else; the eigenproblem shrinks from the block's size (375 in 3D at
// p = 2) to the cell's (81).
Eigen::MatrixXd cell_schur_complement(const Eigen::MatrixXd& A, const std::vector<int>& block_cps,
                                      const std::vector<int>& cell_cps, int dim) {
  std::vector<Eigen::Index> cell, other;
  for (int cp : cell_cps)
    for (int c = 0; c < dim; ++c)
      cell.push_back(static_cast<Eigen::Index>(std::find(block_cps.begin(), block_cps.end(), cp) -
                                               block_cps.begin()) *
                         dim +
                     c);
  std::vector<char> in_cell(static_cast<size_t>(A.rows()), 0);
  for (Eigen::Index i : cell) in_cell[static_cast<size_t>(i)] = 1;
  for (Eigen::Index i = 0; i < A.rows(); ++i)
    if (!in_cell[static_cast<size_t>(i)]) other.push_back(i);
  const Eigen::MatrixXd Acc = A(cell, cell);
  if (other.empty()) return Acc;
  Eigen::MatrixXd Aoo = A(other, other);
  Aoo.diagonal().array() += 1e-12 * Aoo.diagonal().maxCoeff();
  const Eigen::MatrixXd Aoc = A(other, cell);
  return Acc - Aoc.transpose() * Aoo.ldlt().solve(Aoc);
}

}  // namespace

double add_face_terms(const ImmersedContext& context, ImmersedScatter& scatter,
                      std::map<int, double>& penalties, bool loads_only) {
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
    // Under B-bar the supports' traction is B-bar's stress (immersed_bbar.hpp).
    const bool bbar = context.options->volumetric == Volumetric::kBbar;
    const Eigen::RowVectorXd mean_divergence =
        bbar ? cell_mean_divergence(context, static_cast<size_t>(cell)) : Eigen::RowVectorXd();
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
          bbar ? bbar_traction_operator(context, b.normal, at.gradients, mean_divergence)
               : normal_operator(b.normal, dim) * context.elasticity *
                     strain_operator(at.gradients, dim);
      const Eigen::MatrixXd P = held(*term.support, b.normal, dim);
      if (!loads_only) boundary.noalias() += w * T.transpose() * P * T;
      supported.push_back({N, T, P, w});
    }
    Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n, n);
    if (!supported.empty()) {
      double beta = 0.0;
      if (loads_only) {
        const auto found = penalties.find(flat);
        if (found == penalties.end())
          throw nurbs::InputError(
              "immersed analysis: a supported cell has no Nitsche penalty in the assembled "
              "system; assemble the loads with the supports the system was assembled with");
        beta = found->second;
      } else {
        std::vector<int> block_cps;
        const Eigen::MatrixXd A = block_energy(context, e, block_cps);
        beta = context.options->nitsche_factor *
               largest_generalised_eigenvalue(
                   cell_schur_complement(A, block_cps, at.control_points, dim), boundary);
        penalties[flat] = beta;
      }
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
        if (!loads_only)
          K.noalias() += w * (beta * N.transpose() * PN - N.transpose() * PT - PT.transpose() * N);
        const Eigen::VectorXd held_value = g.head(dim);
        f.noalias() += w * (beta * PN.transpose() - PT.transpose()) * held_value;
      }
    }
    if (!loads_only) scatter.add_matrix(at.control_points, K);
    scatter.add_vector(at.control_points, f);
  }
  return max_penalty;
}

}  // namespace isospring::analysis::detail
