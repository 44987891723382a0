// Immersed elasticity: active DOFs, the bulk stiffness and body load over the part's cell
// quadrature, and the input checks (including the rigid-body check on the supported faces).

#include <algorithm>
#include <cmath>
#include <string>

#include "immersed_bbar.hpp"
#include "immersed_kernels.hpp"
#include "immersed_pattern.hpp"
#include "isospring/nurbs/error.hpp"
#include "rigid_modes.hpp"

namespace isospring::analysis {

namespace detail {

Eigen::MatrixXd voigt_elasticity(const LameParameters& lame, int dim) {
  const int v = dim == 2 ? 3 : 6;
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(v, v);
  for (int i = 0; i < dim; ++i) {
    for (int j = 0; j < dim; ++j) D(i, j) = lame.lambda;
    D(i, i) += 2 * lame.mu;
  }
  for (int s = dim; s < v; ++s) D(s, s) = lame.mu;
  return D;
}

Eigen::MatrixXd strain_operator(const Eigen::MatrixXd& g, int dim) {
  const Eigen::Index n = g.rows();
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(dim == 2 ? 3 : 6, n * dim);
  for (Eigen::Index a = 0; a < n; ++a) {
    const Eigen::Index c = a * dim;
    for (int i = 0; i < dim; ++i) B(i, c + i) = g(a, i);
    if (dim == 2) {
      B(2, c) = g(a, 1);
      B(2, c + 1) = g(a, 0);
    } else {
      B(3, c + 1) = g(a, 2), B(3, c + 2) = g(a, 1);  // yz
      B(4, c) = g(a, 2), B(4, c + 2) = g(a, 0);      // xz
      B(5, c) = g(a, 1), B(5, c + 1) = g(a, 0);      // xy
    }
  }
  return B;
}

Eigen::MatrixXd value_operator(const Eigen::VectorXd& values, int dim) {
  Eigen::MatrixXd N = Eigen::MatrixXd::Zero(dim, values.size() * dim);
  for (Eigen::Index a = 0; a < values.size(); ++a)
    for (int c = 0; c < dim; ++c) N(c, a * dim + c) = values[a];
  return N;
}

Eigen::MatrixXd normal_operator(const Eigen::Vector3d& n, int dim) {
  if (dim == 2) return (Eigen::MatrixXd(2, 3) << n.x(), 0, n.y(), 0, n.y(), n.x()).finished();
  return (Eigen::MatrixXd(3, 6) << n.x(), 0, 0, 0, n.z(), n.y(),  //
          0, n.y(), 0, n.z(), 0, n.x(),                           //
          0, 0, n.z(), n.y(), n.x(), 0)
      .finished();
}

// For the isotropic material, K(a i, b j) = sum_q w_q [lambda dN_a/dx_i dN_b/dx_j +
// mu dN_a/dx_j dN_b/dx_i + mu delta_ij grad N_a . grad N_b]: every term is an entry of
// A = G^T W G, G (points x dim * count) the basis gradients and W the weights: one matrix product
// for the cell instead of B^T D B per point, over the cell's reduced rule.
void cell_stiffness(const ImmersedContext& context, size_t c, std::vector<int>& cps,
                    Eigen::MatrixXd& local) {
  const CellRule& cell = context.cell_rules[c];
  const Element& e = context.cell_elements[c];
  const int dim = context.basis.dim();
  const int count = context.basis.count();
  const auto points = static_cast<Eigen::Index>(cell.points.size());
  Eigen::MatrixXd G(points, count * dim), WG(points, count * dim);
  BasisAt at;
  for (Eigen::Index q = 0; q < points; ++q) {
    context.basis.evaluate(e, cell.points[static_cast<size_t>(q)], at);
    for (int k = 0; k < dim; ++k)
      G.row(q).segment(k * count, count) = at.gradients.col(k).transpose();
    WG.row(q) = (cell.weights[static_cast<size_t>(q)] * context.thickness) * G.row(q);
  }
  const Eigen::MatrixXd A = G.transpose() * WG;
  const bool bbar = context.options->volumetric == Volumetric::kBbar;
  const LameParameters lame = bbar ? bbar_deviatoric_lame(context.lame) : context.lame;
  const double lambda = lame.lambda, mu = lame.mu;
  local.resize(count * dim, count * dim);
  for (int b = 0; b < count; ++b)
    for (int a = 0; a < count; ++a) {
      double laplace = 0.0;
      for (int k = 0; k < dim; ++k) laplace += A(k * count + a, k * count + b);
      for (int j = 0; j < dim; ++j)
        for (int i = 0; i < dim; ++i)
          local(a * dim + i, b * dim + j) = lambda * A(i * count + a, j * count + b) +
                                            mu * A(j * count + a, i * count + b) +
                                            (i == j ? mu * laplace : 0.0);
    }
  if (bbar) {
    double volume = 0.0;
    for (double w : cell.weights) volume += w * context.thickness;
    add_mean_dilatation(context, WG, volume, local);
  }
  context.basis.control_points(e, cps);
}

void ImmersedScatter::add_matrix(const std::vector<int>& cps, const Eigen::MatrixXd& local) {
  const int n = static_cast<int>(cps.size());
  for (int b = 0; b < n; ++b)
    for (int a = 0; a < n; ++a) {
      const int na = (*node_of_control_point)[static_cast<size_t>(cps[static_cast<size_t>(a)])];
      const int nb = (*node_of_control_point)[static_cast<size_t>(cps[static_cast<size_t>(b)])];
      for (int j = 0; j < dim; ++j)
        for (int i = 0; i < dim; ++i) {
          const int row = na * dim + i, col = nb * dim + j;
          if (row <= col) triplets.emplace_back(row, col, local(a * dim + i, b * dim + j));
        }
    }
}

void ImmersedScatter::add_vector(const std::vector<int>& cps, const Eigen::VectorXd& local) {
  for (size_t a = 0; a < cps.size(); ++a) {
    const int node = (*node_of_control_point)[static_cast<size_t>(cps[a])];
    for (int c = 0; c < dim; ++c)
      force[node * dim + c] += local[static_cast<Eigen::Index>(a) * dim + c];
  }
}

}  // namespace detail

namespace {

void check_options(const geometry::ImmersedDomain& domain, const ImmersedOptions& options) {
  const auto fail = [](const std::string& m) { throw nurbs::InputError(m); };
  if (domain.cells.empty()) fail("immersed domain: no cell lies in the part");
  const bool planar = options.formulation != Formulation::kSolid;
  if (planar != (domain.dimension == 2))
    fail(std::string("immersed analysis: a ") + (domain.dimension == 2 ? "2D" : "3D") +
         " domain needs formulation " +
         (domain.dimension == 2 ? "plane stress or plane strain" : "solid"));
  check_material(options.material, options.formulation);
  if (options.volumetric == Volumetric::kBbar && options.formulation == Formulation::kPlaneStress)
    fail(
        "immersed analysis: volumetric bbar needs a solid or plane strain (plane stress does not "
        "lock); use the displacement formulation");
  const auto check_face = [&](int face, const std::string& what) {
    if (face < 0 || face >= domain.face_count)
      fail("immersed analysis: " + what + " face " + std::to_string(face) +
           " does not exist; the part has faces 0.." + std::to_string(domain.face_count - 1));
  };
  for (const auto& s : options.supports) {
    check_face(s.face, "support");
    if (!s.symmetry && !s.fixed[0] && !s.fixed[1] && !s.fixed[2])
      fail("immersed analysis: the support on face " + std::to_string(s.face) +
           " holds no component; set fixed components or symmetry");
  }
  for (const auto& t : options.tractions) check_face(t.face, "traction");
  for (const auto& p : options.pressures) check_face(p.face, "pressure");
  if (!(options.nitsche_factor > 2.0))
    fail("immersed analysis: nitsche_factor must exceed 2 (the coercivity bound)");
  if (!(options.ghost_penalty >= 0.0)) fail("immersed analysis: ghost_penalty must be >= 0");
  if (!(options.ghost_fraction >= 0.0 && options.ghost_fraction <= 1.0))
    fail("immersed analysis: ghost_fraction must lie in [0, 1]");
}

// The supports' held directions over their faces must block every rigid motion.
void check_rigid_modes(const geometry::ImmersedDomain& domain, const ImmersedOptions& options) {
  const int dim = domain.dimension;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (const auto& b : domain.boundary) lo = lo.cwiseMin(b.point), hi = hi.cwiseMax(b.point);
  const Eigen::Vector3d centre = 0.5 * (lo + hi);
  const double size = std::max((hi - lo).norm(), 1e-300);
  Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(dim == 2 ? 3 : 6, dim == 2 ? 3 : 6);
  for (const auto& s : options.supports)
    for (const auto& b : domain.boundary) {
      if (b.face != s.face) continue;
      const Eigen::Vector3d x = (b.point - centre) / size;
      Eigen::VectorXd held = Eigen::VectorXd::Zero(gram.rows());
      for (int c = 0; c < dim; ++c) {
        const Eigen::VectorXd row = detail::rigid_mode_row(x, c, dim);
        if (s.symmetry) {
          held += b.normal[c] * row;
        } else if (s.fixed[static_cast<size_t>(c)]) {
          gram.noalias() += b.weight * row * row.transpose();
        }
      }
      if (s.symmetry) gram.noalias() += b.weight * held * held.transpose();
    }
  detail::throw_if_rigid_modes_free(gram, dim, "the immersed part",
                                    "fixed components or symmetry faces");
}

// The cells' elements, the active control points' node numbers and (with `reduce`) each cell's
// reduced rule.
void activate(detail::ImmersedContext& context, ImmersedSystem& system, bool reduce = true) {
  const auto& domain = *context.domain;
  const auto& basis = context.basis;
  system.node_of_control_point.assign(static_cast<size_t>(domain.background.num_points()), -1);
  int total = 1;
  for (int d = 0; d < basis.dim(); ++d) total *= basis.elements(d);
  context.cell_of_element.assign(static_cast<size_t>(total), -1);
  std::vector<int> cps;
  for (size_t c = 0; c < domain.cells.size(); ++c) {
    const auto& cell = domain.cells[c];
    if (cell.points.empty() || cell.points.size() != cell.weights.size())
      throw nurbs::InputError("immersed domain: cell " + std::to_string(c) +
                              " has no points or a weight count that differs from its points");
    const detail::Element e = detail::element_of_cell(basis, cell.points);
    context.cell_elements.push_back(e);
    int& slot = context.cell_of_element[static_cast<size_t>(basis.flat(e))];
    if (slot >= 0)
      throw nurbs::InputError("immersed domain: cells " + std::to_string(slot) + " and " +
                              std::to_string(c) + " lie in the same background element");
    slot = static_cast<int>(c);
    basis.control_points(e, cps);
    for (int cp : cps) system.node_of_control_point[static_cast<size_t>(cp)] = 0;
  }
  // Each cell's rule reduced once: the stiffness, the body load and the Nitsche penalty's local
  // eigenvalue problems (which take a cell's stiffness several times) all use it.
  context.cell_rules.resize(domain.cells.size());
  const long cells = reduce ? static_cast<long>(domain.cells.size()) : 0;
#pragma omp parallel for schedule(dynamic, 16)
  for (long c = 0; c < cells; ++c) {
    const auto& cell = domain.cells[static_cast<size_t>(c)];
    context.cell_rules[static_cast<size_t>(c)] = detail::reduced_cell_rule(
        basis, context.cell_elements[static_cast<size_t>(c)], cell.points, cell.weights);
  }
  int nodes = 0;
  for (size_t a = 0; a < system.node_of_control_point.size(); ++a)
    if (system.node_of_control_point[a] == 0) {
      system.node_of_control_point[a] = nodes++;
      system.control_point_of_node.push_back(static_cast<int>(a));
    }
}

// Bulk stiffness (in place, immersed_pattern.hpp) over the cells' reduced rules, colour by
// colour on OpenMP's threads: the cells of a colour share no control point, so their matrix
// entries do not race, and every sum runs in the same order whatever the thread count.
Eigen::SparseMatrix<double> add_bulk(const detail::ImmersedContext& context,
                                     const ImmersedSystem& system) {
  const int dim = context.domain->dimension;
  const detail::ImmersedPattern pattern(context, system.node_of_control_point,
                                        static_cast<int>(system.control_point_of_node.size()), dim);
  Eigen::SparseMatrix<double> stiffness = pattern.empty_matrix();
  for (const std::vector<long>& colour : pattern.colours()) {
    const long count = static_cast<long>(colour.size());
#pragma omp parallel if (count > 16)
    {
      std::vector<int> cps;
      Eigen::MatrixXd local;
#pragma omp for schedule(dynamic, 8)
      for (long k = 0; k < count; ++k) {
        const size_t c = static_cast<size_t>(colour[static_cast<size_t>(k)]);
        detail::cell_stiffness(context, c, cps, local);
        pattern.add(c, local, stiffness);
      }
    }
  }
  return stiffness;
}

// Body force and gravity over the cells' reduced rules, colour by colour as the stiffness: each
// entry's sum has the same order for any thread count, and in assemble_immersed and
// assemble_immersed_loads alike.
void add_body_load(const detail::ImmersedContext& context, const ImmersedSystem& system,
                   Eigen::VectorXd& force) {
  const auto& options = *context.options;
  const int dim = context.domain->dimension;
  const Eigen::Vector3d load3 = options.body_force + options.material.density * options.gravity;
  const Eigen::VectorXd load = load3.head(dim);
  if (load.isZero(0.0)) return;
  for (const std::vector<long>& colour : detail::cell_colours(context)) {
    const long count = static_cast<long>(colour.size());
#pragma omp parallel if (count > 16)
    {
      detail::BasisAt at;
      std::vector<int> cps;
      Eigen::VectorXd local_force;
#pragma omp for schedule(dynamic, 8)
      for (long k = 0; k < count; ++k) {
        const size_t c = static_cast<size_t>(colour[static_cast<size_t>(k)]);
        const detail::CellRule& rule = context.cell_rules[c];
        context.basis.control_points(context.cell_elements[c], cps);
        local_force.setZero(context.basis.count() * dim);
        for (size_t q = 0; q < rule.points.size(); ++q) {
          context.basis.evaluate(context.cell_elements[c], rule.points[q], at);
          local_force.noalias() += rule.weights[q] * context.thickness *
                                   detail::value_operator(at.values, dim).transpose() * load;
        }
        for (size_t a = 0; a < cps.size(); ++a) {
          const int node = system.node_of_control_point[static_cast<size_t>(cps[a])];
          for (int i = 0; i < dim; ++i)
            force[node * dim + i] += local_force[static_cast<Eigen::Index>(a) * dim + i];
        }
      }
    }
  }
}

detail::ImmersedContext make_context(const geometry::ImmersedDomain& domain,
                                     const ImmersedOptions& options) {
  detail::ImmersedContext context{
      &domain, &options, detail::BackgroundBasis(domain), {}, 1.0, {}, {}, {}, {}, {}};
  context.lame = lame_parameters(options.material, options.formulation);
  context.thickness = options.formulation == Formulation::kSolid ? 1.0 : options.material.thickness;
  context.elasticity = detail::voigt_elasticity(context.lame, domain.dimension);
  return context;
}

// What the loads-only assembly must share with the system: the supports' faces and held
// components (the Nitsche penalties and the traction's free components on supported faces
// follow from them) and the material.
bool same_supports_and_material(const ImmersedOptions& a, const ImmersedOptions& b) {
  bool same = a.supports.size() == b.supports.size() && a.formulation == b.formulation &&
              a.material.youngs_modulus == b.material.youngs_modulus &&
              a.material.poisson_ratio == b.material.poisson_ratio &&
              a.material.thickness == b.material.thickness && a.nitsche_factor == b.nitsche_factor;
  for (size_t s = 0; same && s < a.supports.size(); ++s)
    same = a.supports[s].face == b.supports[s].face && a.supports[s].fixed == b.supports[s].fixed &&
           a.supports[s].symmetry == b.supports[s].symmetry;
  return same;
}

}  // namespace

ImmersedSystem assemble_immersed(const geometry::ImmersedDomain& domain,
                                 const ImmersedOptions& options) {
  check_options(domain, options);
  detail::ImmersedContext context = make_context(domain, options);
  ImmersedSystem system;
  system.dim = domain.dimension;
  system.options = options;
  activate(context, system);
  check_rigid_modes(domain, options);
  const int dofs = static_cast<int>(system.control_point_of_node.size()) * system.dim;
  detail::ImmersedScatter scatter;
  scatter.dim = system.dim;
  scatter.node_of_control_point = &system.node_of_control_point;
  scatter.force = Eigen::VectorXd::Zero(dofs);
  context.ghost = detail::ghost_faces(context);
  const Eigen::SparseMatrix<double> bulk = add_bulk(context, system);
  add_body_load(context, system, scatter.force);
  system.max_nitsche_penalty = detail::add_face_terms(context, scatter, system.nitsche_penalties);
  if (options.ghost_penalty > 0) system.ghost_faces = detail::add_ghost_penalty(context, scatter);
  // The Nitsche and ghost-penalty terms (few cells) as triplets, added to the bulk.
  Eigen::SparseMatrix<double> terms(dofs, dofs);
  terms.setFromTriplets(scatter.triplets.begin(), scatter.triplets.end());
  std::vector<Eigen::Triplet<double>>().swap(scatter.triplets);
  system.stiffness = bulk + terms;
  system.force = std::move(scatter.force);
  return system;
}

Eigen::VectorXd assemble_immersed_loads(const geometry::ImmersedDomain& domain,
                                        const ImmersedOptions& options,
                                        const ImmersedSystem& system) {
  check_options(domain, options);
  if (!same_supports_and_material(options, system.options))
    throw nurbs::InputError(
        "immersed analysis: the loads-only assembly needs the supports (faces and held "
        "components), the material and nitsche_factor the system was assembled with; assemble "
        "the whole system for other ones");
  detail::ImmersedContext context = make_context(domain, options);
  ImmersedSystem located;
  const Eigen::Vector3d body = options.body_force + options.material.density * options.gravity;
  // The cells' reduced rules serve the body load and, under B-bar, the Nitsche terms' cell means.
  activate(context, located,
           !body.head(domain.dimension).isZero(0.0) || options.volumetric == Volumetric::kBbar);
  if (located.node_of_control_point != system.node_of_control_point)
    throw nurbs::InputError(
        "immersed analysis: the loads-only assembly was given another domain than the system's; "
        "assemble the system on this domain");
  detail::ImmersedScatter scatter;
  scatter.dim = system.dim;
  scatter.node_of_control_point = &system.node_of_control_point;
  scatter.force = Eigen::VectorXd::Zero(system.force.size());
  add_body_load(context, system, scatter.force);
  std::map<int, double> penalties = system.nitsche_penalties;
  detail::add_face_terms(context, scatter, penalties, true);
  return std::move(scatter.force);
}

}  // namespace isospring::analysis
