// Total Lagrangian St. Venant-Kirchhoff: element force/tangent, assembly and Newton with load
// stepping.
#include "isospring/analysis/nonlinear_elasticity.hpp"

#include <omp.h>

#include <Eigen/CholmodSupport>
#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <mutex>
#include <sstream>
#include <stdexcept>

#include "assembly_structure.hpp"
#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/constraints.hpp"
#include "isospring/analysis/neo_hookean.hpp"
#include "isospring/analysis/tangent_solver.hpp"
#include "isospring/analysis/thread_scope.hpp"
#include "isospring/nurbs/error.hpp"
#include "reduced_system.hpp"
#include "svk_element.hpp"

namespace isospring::analysis {

namespace {

// The element gradients are kept across calls (the reference geometry never changes) while they
// take at most this much memory: 106 MB for the 8,019-DOF score test of `isospring identify`
// (degree 3, 1,080 elements of 64 points).
constexpr double kGradientCacheBytes = 256e6;

double gradient_bytes(const detail::AssemblyStructure& s, int dim) {
  double bytes = 0.0;
  for (const auto& element : s.elements) {
    const auto& quadrature = s.quadratures[static_cast<size_t>(element.patch)];
    bytes += 8.0 * quadrature.points_per_element() * (dim * quadrature.basis_count() + 1);
  }
  return bytes;
}

}  // namespace

struct SvkAssembler::Impl {
  Impl(const Problem& problem, const DofMap& dofs)
      : structure(problem, dofs),
        dim(dofs.dofs_per_node()),
        thickness(thickness_factor(problem)),
        cache_gradients(gradient_bytes(structure, dim) <= kGradientCacheBytes) {}
  // Every element's gradients, evaluated at the first call (an inverted parametrisation throws
  // there, as without the cache; the next call tries again).
  void fill_gradients(int threads) {
    std::call_once(gradients_filled, [&] {
      gradients.resize(structure.elements.size());
      detail::for_each_element_by_colour<detail::QuadraturePoint>(
          structure, threads, false, [&](int e, detail::QuadraturePoint& point) {
            const auto& element = structure.elements[static_cast<size_t>(e)];
            detail::element_gradients(structure.quadratures[static_cast<size_t>(element.patch)],
                                      element.patch, element.index, dim, thickness, point,
                                      gradients[static_cast<size_t>(e)]);
          });
    });
  }
  detail::AssemblyStructure structure;
  int dim;
  double thickness;
  bool cache_gradients;
  std::once_flag gradients_filled;
  std::vector<detail::ElementGradients> gradients;
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
  if (impl_->cache_gradients) impl_->fill_gradients(threads_);
  if (tangent) s.empty_matrix(*tangent);
  // Colours in parallel by the rule of the linear assembly (detail::colour_in_parallel): one
  // tangent of a degree-3 solid element is ~7 Mflop. The forces alone are light work: on two
  // threads they took 24 ms against 22 (bench_identify_model, BM_SvkForce, 192 elements).
  struct Scratch {
    // Constructed on each thread of the element loop: the element kernel's Eigen products run on
    // that thread (omp_set_num_threads sets the nthreads-var of the current task only, which ends
    // with the loop's parallel region).
    Scratch() { omp_set_num_threads(1); }
    detail::QuadraturePoint point;
    detail::ElementGradients gradients;
    detail::SvkElementScratch kernel;
    Eigen::MatrixXd displacements;
    Eigen::VectorXd local_lambda, local_mu;
    Eigen::MatrixXd local_tangent;
  };
  detail::for_each_element_by_colour<Scratch>(
      s, threads_, tangent && detail::heavy_elements(s), [&](int e, Scratch& scratch) {
        const auto& element = s.elements[static_cast<size_t>(e)];
        const auto& quadrature = s.quadratures[static_cast<size_t>(element.patch)];
        const int* nodes = s.nodes.data() + s.node_offset[static_cast<size_t>(e)];
        const int n = quadrature.basis_count();
        if (!impl_->cache_gradients)
          detail::element_gradients(quadrature, element.patch, element.index, dim, impl_->thickness,
                                    scratch.point, scratch.gradients);
        const detail::ElementGradients& gradients =
            impl_->cache_gradients ? impl_->gradients[static_cast<size_t>(e)] : scratch.gradients;
        scratch.displacements.resize(n, dim);
        for (int a = 0; a < n; ++a)
          for (int c = 0; c < dim; ++c) scratch.displacements(a, c) = u[nodes[a] * dim + c];
        Eigen::MatrixXd* lt = tangent ? &scratch.local_tangent : nullptr;
        if (dim == 2)
          detail::svk_element<2>(gradients, scratch.displacements, lame, scratch.local_lambda,
                                 scratch.local_mu, lt, scratch.kernel);
        else
          detail::svk_element<3>(gradients, scratch.displacements, lame, scratch.local_lambda,
                                 scratch.local_mu, lt, scratch.kernel);
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
