// Total Lagrangian St. Venant-Kirchhoff: element force/tangent, assembly and Newton with load
// stepping.
#include "isospring/analysis/nonlinear_elasticity.hpp"

#include <omp.h>

#include <Eigen/CholmodSupport>
#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "assembly_structure.hpp"
#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/constraints.hpp"
#include "isospring/analysis/validation.hpp"
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
    : impl_(std::make_unique<Impl>(problem, dofs)), num_dofs_(dofs.num_dofs()) {}

SvkAssembler::~SvkAssembler() = default;

namespace {

// Element force (n * dim) and, when `tangent` is set, element tangent of one element.
template <int Dim>
void element_svk(const detail::PatchQuadrature& quadrature, int patch, int element,
                 const int* element_nodes, const Eigen::VectorXd& u, const LameParameters& lame,
                 double thickness, detail::QuadraturePoint& point, Eigen::VectorXd& force,
                 Eigen::MatrixXd* tangent) {
  using Mat = Eigen::Matrix<double, Dim, Dim>;
  const int n = quadrature.basis_count();
  thread_local Eigen::MatrixXd g, ue, fg, gg, gsg;
  g.resize(n, Dim);
  ue.resize(n, Dim);  // element displacements, row a = u_a
  for (int a = 0; a < n; ++a)
    for (int c = 0; c < Dim; ++c) ue(a, c) = u[element_nodes[a] * Dim + c];
  force.setZero(n * Dim);
  if (tangent) tangent->setZero(n * Dim, n * Dim);
  for (int q = 0; q < quadrature.points_per_element(); ++q) {
    quadrature.evaluate(element, q, point);
    const double det = detail::physical_gradients(point, Dim, patch, element, g);
    const double w = point.weight * det * thickness;
    // F_ij = delta_ij + sum_a u_a,i G_a,j.
    const Mat F = Mat::Identity() + ue.transpose().lazyProduct(g);
    const Mat E = 0.5 * (F.transpose() * F - Mat::Identity());
    const Mat S = lame.lambda * E.trace() * Mat::Identity() + 2.0 * lame.mu * E;
    const Mat P = F * S;
    // r_a = P G_a.
    fg.noalias() = g.lazyProduct(P.transpose());  // row a = (P G_a)^T
    for (int a = 0; a < n; ++a)
      for (int i = 0; i < Dim; ++i) force[a * Dim + i] += w * fg(a, i);
    if (!tangent) continue;
    const Eigen::Matrix<double, Eigen::Dynamic, Dim> gF = g.lazyProduct(F.transpose());  // g_a
    const Mat C = F * F.transpose();
    gg.noalias() = g.lazyProduct(g.transpose());
    gsg.noalias() = (g * S).lazyProduct(g.transpose());
    for (int b = 0; b < n; ++b)
      for (int a = 0; a < n; ++a)
        for (int k = 0; k < Dim; ++k)
          for (int i = 0; i < Dim; ++i) {
            double v = lame.lambda * gF(a, i) * gF(b, k) + lame.mu * C(i, k) * gg(a, b) +
                       lame.mu * gF(b, i) * gF(a, k);
            if (i == k) v += gsg(a, b);
            (*tangent)(a * Dim + i, b * Dim + k) += w * v;
          }
  }
}

}  // namespace

Eigen::VectorXd SvkAssembler::internal_force(const Eigen::VectorXd& u, const LameParameters& lame,
                                             Eigen::SparseMatrix<double>* tangent) const {
  const detail::AssemblyStructure& s = impl_->structure;
  const int dim = impl_->dim;
  if (u.size() != num_dofs_)
    throw std::invalid_argument("SvkAssembler: displacement of size " + std::to_string(u.size()) +
                                ", expected " + std::to_string(num_dofs_));
  Eigen::VectorXd force = Eigen::VectorXd::Zero(num_dofs_);
  if (tangent) *tangent = s.empty_matrix();
  std::string error;
  // Elements of one colour share no node: their scatters into `force` and `tangent` never race.
  constexpr int kParallelMinimum = 64;
  for (const auto& colour : s.colours) {
    const int count = static_cast<int>(colour.size());
#pragma omp parallel if (count >= kParallelMinimum)
    {
      detail::QuadraturePoint point;
      Eigen::VectorXd local_force;
      Eigen::MatrixXd local_tangent;
#pragma omp for schedule(dynamic, 16)
      for (int c = 0; c < count; ++c) {
        const int e = colour[static_cast<size_t>(c)];
        const auto& element = s.elements[static_cast<size_t>(e)];
        const auto& quadrature = s.quadratures[static_cast<size_t>(element.patch)];
        const int* nodes = s.nodes.data() + s.node_offset[static_cast<size_t>(e)];
        try {
          if (dim == 2)
            element_svk<2>(quadrature, element.patch, element.index, nodes, u, lame,
                           impl_->thickness, point, local_force,
                           tangent ? &local_tangent : nullptr);
          else
            element_svk<3>(quadrature, element.patch, element.index, nodes, u, lame,
                           impl_->thickness, point, local_force,
                           tangent ? &local_tangent : nullptr);
          const int n = quadrature.basis_count();
          for (int a = 0; a < n; ++a)
            for (int i = 0; i < dim; ++i) force[nodes[a] * dim + i] += local_force[a * dim + i];
          if (tangent) s.scatter(e, local_tangent, *tangent);
        } catch (const std::exception& ex) {
#pragma omp critical(isospring_svk_error)
          if (error.empty()) error = ex.what();
        }
      }
    }
    if (!error.empty()) throw nurbs::InputError(error);
  }
  return force;
}

namespace {

// Factorisation of the free tangent block: CHOLMOD LLT, simplicial LDLT when not positive
// definite (compressive states can make the tangent indefinite; LDLT without pivoting still
// handles the usual non-zero pivots).
class TangentSolver {
 public:
  bool compute(const Eigen::SparseMatrix<double>& upper) {
    llt_.cholmod().print = 0;  // an indefinite tangent is handled below, not printed
    llt_.compute(upper);
    use_llt_ = llt_.info() == Eigen::Success;
    if (use_llt_) return true;
    ldlt_.compute(upper);
    if (ldlt_.info() != Eigen::Success) return false;
    const auto d = ldlt_.vectorD();
    return d.allFinite() && d.cwiseAbs().minCoeff() > 0.0;
  }
  Eigen::VectorXd solve(const Eigen::VectorXd& rhs) const {
    return use_llt_ ? Eigen::VectorXd(llt_.solve(rhs)) : Eigen::VectorXd(ldlt_.solve(rhs));
  }

 private:
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Upper> llt_;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Upper> ldlt_;
  bool use_llt_ = true;
};

struct StepOutcome {
  bool converged = false;
  int iterations = 0;
  double residual = 0.0;
};

// Newton at load factor t from `u` (updated in place; prescribed DOFs set to t * values).
StepOutcome newton(const SvkAssembler& assembler, const LameParameters& lame,
                   const Constraints& constraints, const Eigen::VectorXd& force, double t,
                   const NonlinearOptions& options, Eigen::VectorXd& u) {
  for (size_t k = 0; k < constraints.dofs.size(); ++k)
    u[constraints.dofs[k]] = t * constraints.values[k];
  StepOutcome out;
  Eigen::SparseMatrix<double> tangent;
  std::vector<bool> fixed(static_cast<size_t>(u.size()), false);
  for (int d : constraints.dofs) fixed[static_cast<size_t>(d)] = true;
  for (int it = 0; it <= options.max_iterations; ++it) {
    const Eigen::VectorXd internal = assembler.internal_force(u, lame, &tangent);
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
    if (std::sqrt(free_norm) <= options.tolerance * scale || free_norm == 0.0) {
      out.converged = true;
      return out;
    }
    if (it == options.max_iterations) return out;
    // Correction on the free DOFs (prescribed ones are already at their values: zero increment).
    Constraints zero = constraints;
    std::fill(zero.values.begin(), zero.values.end(), 0.0);
    const detail::ReducedSystem reduced(tangent, zero);
    TangentSolver solver;
    if (!solver.compute(reduced.free_matrix)) return out;
    u += reduced.expand(solver.solve(reduced.free_rhs(r)));
    ++out.iterations;
  }
  return out;
}

class ThreadScope {
 public:
  explicit ThreadScope(int threads) : previous_(omp_get_max_threads()) {
    if (threads > 0) omp_set_num_threads(threads);
  }
  ~ThreadScope() { omp_set_num_threads(previous_); }

 private:
  int previous_;
};

}  // namespace

std::vector<NonlinearLoadCaseResult> solve_static_nonlinear(const Problem& problem,
                                                            const NonlinearOptions& options) {
  validate_problem(problem);
  const ThreadScope threads(options.threads);
  const DofMap dofs(problem);
  const Constraints constraints = build_constraints(problem, dofs);
  check_rigid_body_modes(problem, dofs, constraints);
  const SvkAssembler assembler(problem, dofs);
  const LameParameters lame = lame_parameters(problem.material, problem.formulation);
  const int dim = dofs.dofs_per_node();

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
          newton(assembler, lame, constraints, force, target, options, trial);
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
        message << "load case \"" << load.id
                << "\": Newton's method for the large-deformation (St. Venant-Kirchhoff) solve "
                   "did not converge beyond load factor "
                << t << " (last relative residual " << outcome.residual << " after "
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
