// Total Lagrangian St. Venant-Kirchhoff: element force/tangent, assembly and Newton with load
// stepping.
#include "isospring/analysis/nonlinear_elasticity.hpp"

#include <Eigen/CholmodSupport>
#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <sstream>
#include <stdexcept>

#include "assembly_structure.hpp"
#include "dense_products.hpp"
#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/constraints.hpp"
#include "isospring/analysis/neo_hookean.hpp"
#include "isospring/analysis/tangent_solver.hpp"
#include "isospring/analysis/thread_scope.hpp"
#include "isospring/nurbs/error.hpp"
#include "reduced_system.hpp"

namespace isospring::analysis {

struct SvkAssembler::Impl {
  Impl(const Problem& problem, const DofMap& dofs)
      : structure(problem, dofs), dim(dofs.dofs_per_node()), thickness(thickness_factor(problem)) {}
  detail::AssemblyStructure structure;
  int dim;
  double thickness;
};

SvkAssembler::SvkAssembler(const Problem& problem, const DofMap& dofs)
    : impl_(std::make_unique<Impl>(problem, dofs)), num_dofs_(dofs.num_dofs()) {
  // Large deformations use the displacement strain throughout (no F-bar).
  if (problem.volumetric == Volumetric::kBbar)
    throw nurbs::InputError(
        "\"volumetric\": \"bbar\" is linear elasticity only; large deformations (SVK) use "
        "\"displacement\"");
}

SvkAssembler::~SvkAssembler() = default;

namespace {

using detail::product_transpose;

// Element forces of unit lambda (S = tr(E) I) and unit mu (S = 2 E), each n * Dim, and, when
// `tangent` is set, the element tangent for `lame`. The tangent's four terms are sums over the
// quadrature points of outer products; they are formed as matrix products over all points at
// once (columns of point q side by side), several times faster than scalar loops in 3D.
template <int Dim>
void element_svk(const detail::PatchQuadrature& quadrature, int patch, int element,
                 const int* element_nodes, const Eigen::VectorXd& u, const LameParameters& lame,
                 double thickness, detail::QuadraturePoint& point, Eigen::VectorXd& force_lambda,
                 Eigen::VectorXd& force_mu, Eigen::MatrixXd* tangent) {
  using Mat = Eigen::Matrix<double, Dim, Dim>;
  const int n = quadrature.basis_count();
  const int nq = quadrature.points_per_element();
  constexpr int kPairs = Dim * (Dim + 1) / 2;  // (i, k) with i <= k
  thread_local Eigen::MatrixXd g, ue, all, geometric;
  thread_local std::array<Eigen::MatrixXd, Dim> mapped, mapped_weighted;  // g_a,c = (F G_a)_c
  thread_local std::array<Eigen::MatrixXd, kPairs> metric;                // blocks w (F F^T)_ik G
  g.resize(n, Dim);
  ue.resize(n, Dim);  // element displacements, row a = u_a
  for (int a = 0; a < n; ++a)
    for (int c = 0; c < Dim; ++c) ue(a, c) = u[element_nodes[a] * Dim + c];
  force_lambda.setZero(n * Dim);
  force_mu.setZero(n * Dim);
  if (tangent) {
    all.resize(n, nq * Dim);
    geometric.resize(n, nq * Dim);
    for (int c = 0; c < Dim; ++c) {
      mapped[static_cast<size_t>(c)].resize(n, nq);
      mapped_weighted[static_cast<size_t>(c)].resize(n, nq);
    }
    for (auto& m : metric) m.resize(n, nq * Dim);
  }
  for (int q = 0; q < nq; ++q) {
    quadrature.evaluate(element, q, point);
    const double det = detail::physical_gradients(point, Dim, patch, element, g);
    const double w = point.weight * det * thickness;
    // F_ij = delta_ij + sum_a u_a,i G_a,j.
    const Mat F = Mat::Identity() + ue.transpose().lazyProduct(g);
    const Mat E = 0.5 * (F.transpose() * F - Mat::Identity());
    // r_a = P G_a with P = F S: row a of g P^T.
    const Eigen::Matrix<double, Eigen::Dynamic, Dim> rl =
        g.lazyProduct((E.trace() * F).transpose());
    const Eigen::Matrix<double, Eigen::Dynamic, Dim> rm = g.lazyProduct((2.0 * F * E).transpose());
    for (int a = 0; a < n; ++a)
      for (int i = 0; i < Dim; ++i) {
        force_lambda[a * Dim + i] += w * rl(a, i);
        force_mu[a * Dim + i] += w * rm(a, i);
      }
    if (!tangent) continue;
    const Mat S = lame.lambda * E.trace() * Mat::Identity() + 2.0 * lame.mu * E;
    const Mat C = F * F.transpose();
    const Eigen::Matrix<double, Eigen::Dynamic, Dim> gF = g.lazyProduct(F.transpose());
    for (int c = 0; c < Dim; ++c) {
      mapped[static_cast<size_t>(c)].col(q) = gF.col(c);
      mapped_weighted[static_cast<size_t>(c)].col(q) = w * gF.col(c);
    }
    all.middleCols(q * Dim, Dim) = g;
    geometric.middleCols(q * Dim, Dim) = w * g.lazyProduct(S);
    int pair = 0;
    for (int i = 0; i < Dim; ++i)
      for (int k = i; k < Dim; ++k, ++pair)
        metric[static_cast<size_t>(pair)].middleCols(q * Dim, Dim) = (w * C(i, k)) * g;
  }
  if (!tangent) return;
  // K_(a,i),(b,k) = lambda M_ik(a,b) + mu M_ki(a,b) + mu Q_ik(a,b) + delta_ik Z(a,b) with
  // M_ik = sum_q w g_.,i g_.,k^T, Q_ik = sum_q w C_ik G G^T, Z = sum_q w G S G^T.
  thread_local Eigen::MatrixXd z;
  thread_local std::array<Eigen::MatrixXd, Dim * Dim> m;
  thread_local std::array<Eigen::MatrixXd, kPairs> qm;
  product_transpose(geometric, all, z);
  // M_ki = M_ik^T: only the products with i <= k are formed.
  for (int i = 0; i < Dim; ++i)
    for (int k = i; k < Dim; ++k)
      product_transpose(mapped_weighted[static_cast<size_t>(i)], mapped[static_cast<size_t>(k)],
                        m[static_cast<size_t>(i * Dim + k)]);
  for (int pair = 0; pair < kPairs; ++pair)
    product_transpose(metric[static_cast<size_t>(pair)], all, qm[static_cast<size_t>(pair)]);
  tangent->resize(n * Dim, n * Dim);
  int pair = 0;
  for (int i = 0; i < Dim; ++i)
    for (int k = i; k < Dim; ++k, ++pair) {
      const Eigen::MatrixXd& mik = m[static_cast<size_t>(i * Dim + k)];
      const Eigen::MatrixXd& qik = qm[static_cast<size_t>(pair)];
      for (int b = 0; b < n; ++b)
        for (int a = 0; a < n; ++a) {
          double v = lame.lambda * mik(a, b) + lame.mu * (mik(b, a) + qik(a, b));
          if (i == k) v += z(a, b);
          (*tangent)(a * Dim + i, b * Dim + k) = v;
          (*tangent)(b * Dim + k, a * Dim + i) = v;
        }
    }
}

}  // namespace

Eigen::VectorXd SvkAssembler::internal_force(const Eigen::VectorXd& u, const LameParameters& lame,
                                             Eigen::SparseMatrix<double>* tangent) const {
  Eigen::VectorXd force_lambda, force_mu;
  internal_force_parts(u, force_lambda, force_mu, lame, tangent);
  return lame.lambda * force_lambda + lame.mu * force_mu;
}

void SvkAssembler::internal_force_parts(const Eigen::VectorXd& u, Eigen::VectorXd& force_lambda,
                                        Eigen::VectorXd& force_mu, const LameParameters& lame,
                                        Eigen::SparseMatrix<double>* tangent) const {
  const detail::AssemblyStructure& s = impl_->structure;
  const int dim = impl_->dim;
  if (u.size() != num_dofs_)
    throw std::invalid_argument("SvkAssembler: displacement of size " + std::to_string(u.size()) +
                                ", expected " + std::to_string(num_dofs_));
  force_lambda.setZero(num_dofs_);
  force_mu.setZero(num_dofs_);
  if (tangent) *tangent = s.empty_matrix();
  // Colours in parallel by the rule of the linear assembly (detail::colour_in_parallel): one
  // tangent of a degree-3 solid element is ~14 Mflop. The forces alone are light work: on two
  // threads they took 24 ms against 22 (bench_identify_model, BM_SvkForce, 192 elements).
  struct Scratch {
    detail::QuadraturePoint point;
    Eigen::VectorXd local_lambda, local_mu;
    Eigen::MatrixXd local_tangent;
  };
  detail::for_each_element_by_colour<Scratch>(
      s, threads_, tangent && detail::heavy_elements(s), [&](int e, Scratch& scratch) {
        const auto& element = s.elements[static_cast<size_t>(e)];
        const auto& quadrature = s.quadratures[static_cast<size_t>(element.patch)];
        const int* nodes = s.nodes.data() + s.node_offset[static_cast<size_t>(e)];
        Eigen::MatrixXd* lt = tangent ? &scratch.local_tangent : nullptr;
        if (dim == 2)
          element_svk<2>(quadrature, element.patch, element.index, nodes, u, lame, impl_->thickness,
                         scratch.point, scratch.local_lambda, scratch.local_mu, lt);
        else
          element_svk<3>(quadrature, element.patch, element.index, nodes, u, lame, impl_->thickness,
                         scratch.point, scratch.local_lambda, scratch.local_mu, lt);
        const int n = quadrature.basis_count();
        for (int a = 0; a < n; ++a)
          for (int i = 0; i < dim; ++i) {
            force_lambda[nodes[a] * dim + i] += scratch.local_lambda[a * dim + i];
            force_mu[nodes[a] * dim + i] += scratch.local_mu[a * dim + i];
          }
        if (tangent) s.scatter(e, scratch.local_tangent, *tangent);
      });
}

namespace {

struct StepOutcome {
  bool converged = false;
  int iterations = 0;
  double residual = 0.0;
};

// The material's internal force r(u) and, when the pointer is set, its tangent (upper triangle).
using InternalForce =
    std::function<Eigen::VectorXd(const Eigen::VectorXd& u, Eigen::SparseMatrix<double>* tangent)>;

// Newton at load factor t from `u` (updated in place; prescribed DOFs end at t * values).
// The first correction moves the prescribed DOFs to their new values through the tangent at the
// last converged state (K_ff du_f = r_f - K_fc du_c), so the free DOFs follow them: moving them
// alone first would squeeze the elements next to a driven side (at a 30 % end stretch of a
// neo-Hookean block Newton then needed 16 halved steps instead of one).
StepOutcome newton(const InternalForce& internal_force, const Constraints& constraints,
                   const Eigen::VectorXd& force, double t, const NonlinearOptions& options,
                   Eigen::VectorXd& u) {
  StepOutcome out;
  Eigen::SparseMatrix<double> tangent;
  std::vector<bool> fixed(static_cast<size_t>(u.size()), false);
  for (int d : constraints.dofs) fixed[static_cast<size_t>(d)] = true;
  Constraints increment = constraints;  // t * values - u on the prescribed DOFs
  for (int it = 0; it <= options.max_iterations; ++it) {
    bool at_target = true;
    for (size_t k = 0; k < constraints.dofs.size(); ++k) {
      increment.values[k] = t * constraints.values[k] - u[constraints.dofs[k]];
      at_target = at_target && increment.values[k] == 0.0;
    }
    const Eigen::VectorXd internal = internal_force(u, &tangent);
    const Eigen::VectorXd r = t * force - internal;
    double free_norm = 0.0, load_norm = 0.0, reaction_norm = 0.0;
    for (Eigen::Index d = 0; d < r.size(); ++d) {
      if (fixed[static_cast<size_t>(d)]) {
        reaction_norm += internal[d] * internal[d];
      } else {
        free_norm += r[d] * r[d];
        load_norm += t * t * force[d] * force[d];
      }
    }
    const double scale = std::sqrt(std::max(load_norm, reaction_norm));
    out.residual = scale > 0.0 ? std::sqrt(free_norm) / scale : std::sqrt(free_norm);
    if (!std::isfinite(out.residual)) return out;
    if (at_target && (std::sqrt(free_norm) <= options.tolerance * scale || free_norm == 0.0)) {
      out.converged = true;
      return out;
    }
    if (it == options.max_iterations) return out;
    const detail::ReducedSystem reduced(tangent, increment);
    TangentSolver solver;
    if (!solver.compute(reduced.free_matrix)) return out;
    u += reduced.expand(solver.solve(reduced.free_rhs(r)));
    // Exactly at their values from now on (u + (t v - u) may differ from t v in the last bit).
    for (size_t k = 0; k < constraints.dofs.size(); ++k)
      u[constraints.dofs[k]] = t * constraints.values[k];
    ++out.iterations;
  }
  return out;
}

}  // namespace

std::vector<NonlinearLoadCaseResult> solve_static_nonlinear(const Problem& problem,
                                                            const NonlinearOptions& options) {
  const ThreadScope threads(options.threads);
  const SupportedProblem supported = number_and_support(problem);
  const DofMap& dofs = supported.dofs;
  const Constraints& constraints = supported.constraints;
  const int dim = dofs.dofs_per_node();

  const bool neo_hookean = options.material == HyperelasticMaterial::kNeoHookean;
  std::unique_ptr<SvkAssembler> svk;
  std::unique_ptr<NeoHookeanAssembler> neo;
  InternalForce internal_force;
  if (neo_hookean) {
    const NeoHookeanParameters moduli =
        neo_hookean_parameters(problem.material, problem.formulation);
    neo = std::make_unique<NeoHookeanAssembler>(problem, dofs);
    internal_force = [&neo, moduli](const Eigen::VectorXd& u, Eigen::SparseMatrix<double>* k) {
      return neo->internal_force(u, moduli, k);
    };
  } else {
    const LameParameters lame = lame_parameters(problem.material, problem.formulation);
    svk = std::make_unique<SvkAssembler>(problem, dofs);
    internal_force = [&svk, lame](const Eigen::VectorXd& u, Eigen::SparseMatrix<double>* k) {
      return svk->internal_force(u, lame, k);
    };
  }
  const char* law = neo_hookean ? "neo-Hookean" : "St. Venant-Kirchhoff";

  std::vector<NonlinearLoadCaseResult> results;
  for (const LoadCase& load : problem.load_cases) {
    NonlinearLoadCaseResult out;
    out.id = load.id;
    const Eigen::VectorXd force = assemble_load(problem, dofs, load);
    Eigen::VectorXd u = Eigen::VectorXd::Zero(dofs.num_dofs());
    double t = 0.0;
    double step = 1.0 / std::max(1, options.initial_steps);
    int halvings = 0;
    while (t < 1.0) {
      const double target = std::min(1.0, t + step);
      Eigen::VectorXd trial = u;
      const StepOutcome outcome =
          newton(internal_force, constraints, force, target, options, trial);
      out.iterations += outcome.iterations;
      if (outcome.converged) {
        u = std::move(trial);
        t = target;
        out.residual = outcome.residual;
        ++out.load_steps;
        halvings = 0;
        continue;
      }
      if (++halvings > options.max_step_halvings) {
        std::ostringstream message;
        message << "load case \"" << load.id << "\": Newton's method for the large-deformation ("
                << law << ") solve did not converge beyond load factor " << t
                << " (last relative residual " << outcome.residual << " after "
                << options.max_step_halvings
                << " step halvings); the load may exceed a limit point (buckling or snap-through) "
                   "or the deformation is too large for the mesh";
        throw std::runtime_error(message.str());
      }
      step *= 0.5;
    }
    out.control_displacements.resize(problem.patches.size());
    for (size_t p = 0; p < problem.patches.size(); ++p) {
      auto& cu = out.control_displacements[p];
      cu.assign(static_cast<size_t>(problem.patches[p].num_points()), Eigen::Vector3d::Zero());
      for (size_t i = 0; i < cu.size(); ++i) {
        for (int c = 0; c < dim; ++c)
          cu[i][c] = u[dofs.dof(static_cast<int>(p), static_cast<int>(i), c)];
        out.max_displacement = std::max(out.max_displacement, cu[i].norm());
      }
    }
    out.displacement = std::move(u);
    results.push_back(std::move(out));
  }
  return results;
}

}  // namespace isospring::analysis
