// ForwardModel with nonlinear terms (geometric nonlinearity): Newton per load case (its first
// iterate is the linear solution), load stepping when that fails, and the exact parameter
// derivatives from the tangent at the converged state (implicit function theorem:
// R(u(theta), theta) = f(theta)). With ModelTerms::nonlinear_weight the prediction blends the
// linear and nonlinear solutions, u = (1 - w) u_lin + w u_nl, with exact derivatives of both.
#include <Eigen/CholmodSupport>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <exception>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>

#include "factorization_cache.hpp"
#include "free_block.hpp"
#include "isospring/analysis/tangent_solver.hpp"
#include "isospring/fitting/identify_model.hpp"

namespace isospring::fitting {

struct ForwardModel::NonlinearCache {
  std::mutex mutex;
  std::vector<Eigen::VectorXd> solutions;         // per load case; empty until solved
  std::vector<Eigen::VectorXd> linear_solutions;  // the linear solution at the same theta, or empty
  // The factorisations of an evaluation, kept so that the next one reuses their symbolic
  // analyses (the tangent's pattern does not change with u or theta); one evaluation at a time.
  std::mutex solver_mutex;
  analysis::TangentSolver linear_solver;
  // Per load case: its last factorised tangent (valid once factorised), the chord matrix of the
  // next evaluation's Newton iterations.
  std::vector<std::shared_ptr<analysis::TangentSolver>> tangent_solvers;
  std::vector<char> factorised;  // not vector<bool>: load cases write theirs concurrently
};

std::shared_ptr<ForwardModel::NonlinearCache> ForwardModel::make_nonlinear_cache() {
  return std::make_shared<NonlinearCache>();
}

namespace {

constexpr double kTolerance = 1e-10;  // |r_free| relative to the load (or the reactions)
constexpr int kMaxIterations = 30;
constexpr int kMaxSteps = 64;  // load steps of the last attempt
// Chord (modified Newton) steps reuse the last factorised tangent of the load case instead of
// assembling and factorising a new one: a fit's next evaluation is at a nearby theta, where they
// converge fast, and the element tangents are most of a Newton iteration's cost (~14 Mflop per
// degree-3 solid element against ~1 for its forces; measured on the suite's large-deformation
// cantilever: 46 % of identify's time in their dense products). A chord step that reduces the
// residual by less than kChordRate is undone and replaced by a Newton step, after which chord
// steps resume on the new tangent (measured on the suite's tube_graded, whose shear load cases
// converge slowly at first: the two score tests of the large-deformation candidate took 9 and 5
// tangents instead of 12 and 10 when one slow chord step stopped them for the solve).
constexpr double kChordRate = 0.25;
constexpr int kMaxChordSteps = 12;

}  // namespace

ModelEvaluation ForwardModel::evaluate_nonlinear(const Eigen::VectorXd& theta,
                                                 bool with_jacobian) const {
  if (!nonlinear_cache_) throw std::logic_error("ForwardModel: nonlinear cache missing");
  const std::lock_guard<std::mutex> solver_lock(nonlinear_cache_->solver_mutex);
  FactorizationCache& shared = *linear_cache_;
  const std::lock_guard<std::mutex> shared_lock(shared.nonlinear_mutex);
  const int nf = static_cast<int>(free_dofs_.size());
  const size_t nt = terms_.stiffness.size();
  std::vector<double> c(nt);
  std::vector<Eigen::VectorXd> dc(nt);
  Eigen::SparseMatrix<double> kff(nf, nf);
  for (size_t j = 0; j < nt; ++j) {
    c[j] = terms_.stiffness[j].coefficient(theta, &dc[j]);
    kff += c[j] * free_blocks_[j];
  }
  // Values and gradients of the nonlinear coefficients, per nonlinear term.
  const size_t nn = terms_.nonlinear.size();
  std::vector<std::vector<double>> e(nn);
  std::vector<std::vector<Eigen::VectorXd>> de(nn);
  for (size_t t = 0; t < nn; ++t)
    for (const Coefficient& coefficient : terms_.nonlinear[t].coefficients) {
      Eigen::VectorXd g;
      e[t].push_back(coefficient(theta, &g));
      de[t].push_back(g);
    }

  // Internal force at u: K u + sum_k e_k n_k(u) with K = sum_j c_j K_j, summed once here: a
  // Newton solve evaluates the force ~10 times per load case, and a product with each K_j costs
  // as much as one with their sum (measured on the suite's tube_graded with a stiffness
  // gradient, 8 terms: a force evaluation 95 -> 52 ms). The nonlinear parts and the free
  // tangent block come along.
  Eigen::SparseMatrix<double> stiffness(num_dofs_, num_dofs_);
  for (size_t j = 0; j < nt; ++j) stiffness += c[j] * terms_.stiffness[j].matrix;
  using Parts = std::vector<std::vector<Eigen::VectorXd>>;  // per nonlinear term, n_k(u)
  auto internal_force = [&](const Eigen::VectorXd& u, Parts& parts,
                            Eigen::SparseMatrix<double>* tangent_ff) {
    parts.resize(nn);
    Eigen::VectorXd r = stiffness * u;
    if (tangent_ff) *tangent_ff = kff;
    for (size_t t = 0; t < nn; ++t) {
      Eigen::SparseMatrix<double> tangent;
      terms_.nonlinear[t].evaluate(u, e[t], parts[t], tangent_ff ? &tangent : nullptr);
      for (size_t k = 0; k < parts[t].size(); ++k) r += e[t][k] * parts[t][k];
      if (tangent_ff) *tangent_ff += detail::free_upper_block(tangent, free_index_, nf);
    }
    return r;
  };

  // Linear solution and its derivatives (only needed for the blend).
  const int w_index = terms_.nonlinear_weight;
  const double w = w_index >= 0 ? theta[w_index] : 1.0;
  analysis::TangentSolver& linear_solver = nonlinear_cache_->linear_solver;
  if (w_index >= 0 && !linear_solver.compute(kff))
    throw std::runtime_error(
        "the stiffness at the current parameters is not positive definite (a parameter left "
        "its physical range, e.g. a negative Young's modulus or nu >= 0.5)");

  // The Jacobian needs the tangent at the converged state unless the blend weight is 0: there
  // du/dtheta = du_lin/dtheta and du/dw = u_nl - u_lin, so u_nl itself is all that is needed
  // (the score screening of the candidate evaluates exactly there, at its neutral w = 0).
  const bool need_tangent = with_jacobian && w != 0.0;

  // Newton at load factor s (loads and prescribed values scaled) from u, updated in place,
  // with chord steps while they converge fast: on `solver` when it holds a factorised tangent
  // (`factorised`), else on `borrowed` (another model's last tangent at the same free DOFs),
  // else on the linear stiffness (the tangent at u = 0, factorised for the blend), which is all
  // a small deformation needs. On success at s = 1 with need_tangent,
  // `solver` holds the factorised tangent at the converged u (else that factorisation is
  // skipped: no solve needs it).
  // The chord steps of the load cases that run at the same time share the linear stiffness's
  // factor, whose solves share CHOLMOD's workspace: one at a time.
  std::mutex linear_solver_mutex;
  auto newton = [&](const Eigen::VectorXd& force, double s, Eigen::VectorXd& u,
                    analysis::TangentSolver& solver, bool& factorised,
                    const analysis::TangentSolver* borrowed, Parts& parts) {
    for (int d = 0; d < num_dofs_; ++d)
      if (free_index_[static_cast<size_t>(d)] < 0) u[d] = s * prescribed_[d];
    // The residual on the free DOFs, and whether it meets the tolerance.
    auto residual = [&](const Eigen::VectorXd& internal, Eigen::VectorXd& r_free) {
      r_free.resize(nf);
      double load = 0.0, reaction = 0.0;
      for (int d = 0; d < num_dofs_; ++d) {
        const int k = free_index_[static_cast<size_t>(d)];
        if (k >= 0) {
          r_free[k] = s * force[d] - internal[d];
          load += s * s * force[d] * force[d];
        } else {
          reaction += internal[d] * internal[d];
        }
      }
      const double norm = r_free.norm();
      return norm <= kTolerance * std::sqrt(std::max(load, reaction)) || norm == 0.0;
    };
    auto step = [&](const analysis::TangentSolver& factor, const Eigen::VectorXd& r_free) {
      const Eigen::VectorXd du = factor.solve(r_free);
      for (int k = 0; k < nf; ++k) u[free_dofs_[static_cast<size_t>(k)]] += du[k];
    };
    Eigen::SparseMatrix<double> tangent_ff;
    Eigen::VectorXd r_free, before_chord, r_before_chord;
    double norm_before_chord = 0.0;
    bool after_chord = false;
    int chords = 0;
    for (int it = 0; it <= kMaxIterations; ++it) {
      bool converged = residual(internal_force(u, parts, nullptr), r_free);
      const double norm = r_free.norm();
      if (!std::isfinite(norm)) {
        if (!after_chord) return false;
        converged = false;
      }
      if (after_chord && !converged && !(norm <= kChordRate * norm_before_chord)) {
        u = before_chord;  // too slow: a Newton step from where the chord step started
        r_free = r_before_chord;
      } else if (converged && !(need_tangent && s == 1.0)) {
        return true;
      } else if (!converged && (factorised || borrowed || w_index >= 0) &&
                 chords < kMaxChordSteps) {
        before_chord = u;
        r_before_chord = r_free;
        norm_before_chord = norm;
        after_chord = true;
        ++chords;
        if (factorised || borrowed) {
          step(factorised ? solver : *borrowed, r_free);
        } else {
          const std::lock_guard<std::mutex> lock(linear_solver_mutex);
          step(linear_solver, r_free);
        }
        continue;
      }
      after_chord = false;
      if (it == kMaxIterations) return false;
      internal_force(u, parts, &tangent_ff);
      factorised = solver.compute(tangent_ff);
      if (!factorised) return false;
      if (converged) return true;
      step(solver, r_free);
    }
    return false;
  };

  // Right-hand sides df/dtheta - dK/dtheta v for the linear terms at displacement v.
  auto linear_rhs = [&](const Eigen::MatrixXd& dforce, const Eigen::VectorXd& v) {
    Eigen::MatrixXd rhs = dforce;
    for (size_t j = 0; j < nt; ++j)
      if (dc[j].cwiseAbs().maxCoeff() > 0.0)
        rhs -= (terms_.stiffness[j].matrix * v) * dc[j].transpose();
    return rhs;
  };
  auto solve_free = [&](const analysis::TangentSolver& factor, const Eigen::MatrixXd& rhs) {
    Eigen::MatrixXd rhs_free(nf, rhs.cols());
    for (int k = 0; k < nf; ++k) rhs_free.row(k) = rhs.row(free_dofs_[static_cast<size_t>(k)]);
    const Eigen::MatrixXd x_free = factor.solve(rhs_free);
    Eigen::MatrixXd x = Eigen::MatrixXd::Zero(num_dofs_, rhs.cols());
    for (int k = 0; k < nf; ++k) x.row(free_dofs_[static_cast<size_t>(k)]) = x_free.row(k);
    return x;
  };

  // First, one load case after the other: the loads, the linear solutions and their
  // derivatives (solves with the one linear factor), and every per-load-case slot of the caches
  // (so that the load cases below only write their own).
  const int nl = num_load_cases_;
  const auto nls = static_cast<size_t>(nl);
  std::vector<Eigen::VectorXd> forces(nls), u_linear(nls);
  std::vector<Eigen::MatrixXd> dforces(nls), du_linear(nls);
  // K u = f - K u_c on the free DOFs, as ForwardModel::evaluate.
  const Eigen::VectorXd ku_c = stiffness * prescribed_;
  for (int l = 0; l < nl; ++l) {
    const auto lc = static_cast<size_t>(l);
    load_vector(l, theta, with_jacobian, forces[lc], dforces[lc]);
    if (w_index >= 0) {
      u_linear[lc] = prescribed_ + solve_free(linear_solver, forces[lc] - ku_c).col(0);
      if (with_jacobian)
        du_linear[lc] = solve_free(linear_solver, linear_rhs(dforces[lc], u_linear[lc]));
    }
  }
  NonlinearCache& cache = *nonlinear_cache_;
  if (cache.tangent_solvers.size() < nls) {
    cache.tangent_solvers.resize(nls);
    cache.factorised.resize(nls, 0);
  }
  for (auto& owned : cache.tangent_solvers)
    if (!owned) owned = std::make_shared<analysis::TangentSolver>();
  auto grow = [nls](auto& per_load_case) {
    if (per_load_case.size() < nls) per_load_case.resize(nls);
  };
  grow(shared.nonlinear_starts), grow(shared.linear_starts);
  grow(shared.tangents), grow(shared.tangent_free_dofs);
  {
    const std::lock_guard<std::mutex> lock(cache.mutex);
    grow(cache.solutions), grow(cache.linear_solutions);
  }

  // Then the Newton solves, the load cases on the nonlinear terms' threads (each load case on
  // one: the element loops inside run serially then). A load case reads and writes only its own
  // slots, so the numbers do not depend on the thread count or the order.
  int team = 1;
  for (const NonlinearTerm& term : terms_.nonlinear) team = std::max(team, term.threads);
  team = std::min(team, nl);
  ModelEvaluation out;
  out.predictions.resize(nls), out.jacobians.resize(nls), out.displacements.resize(nls);
  std::vector<std::exception_ptr> errors(nls);
#pragma omp parallel for schedule(dynamic) num_threads(team) if (team > 1)
  for (int l = 0; l < nl; ++l) {
    const auto lc = static_cast<size_t>(l);
    try {
      // Newton from the last solution, this model's or another's (FactorizationCache), moved by
      // the change of the linear solution since: u_lin(theta) + (u_nl - u_lin)(theta_last), a
      // first-order predictor (the linear part follows a new modulus or stiffness gradient
      // exactly, the nonlinear part is carried over). Else from zero (its first step is the
      // linear solution), then in 2, 4, ... equal load steps.
      const std::shared_ptr<analysis::TangentSolver>& owned_solver = cache.tangent_solvers[lc];
      analysis::TangentSolver& solver = *owned_solver;
      bool factorised = cache.factorised[lc] != 0;
      Eigen::VectorXd u, u_linear_then;
      {
        const std::lock_guard<std::mutex> lock(cache.mutex);
        u = cache.solutions[lc];
        u_linear_then = cache.linear_solutions[lc];
      }
      // This model's first evaluation: another model's solution and tangent.
      if (u.size() != num_dofs_ && shared.nonlinear_starts[lc].size() == num_dofs_) {
        u = shared.nonlinear_starts[lc];
        u_linear_then = shared.linear_starts[lc];
      }
      if (u.size() == num_dofs_ && u_linear[lc].size() == num_dofs_ &&
          u_linear_then.size() == num_dofs_)
        u += u_linear[lc] - u_linear_then;
      const analysis::TangentSolver* borrowed = nullptr;
      if (!factorised && shared.tangents[lc] && shared.tangents[lc] != owned_solver &&
          shared.tangent_free_dofs[lc] == free_dofs_)
        borrowed = shared.tangents[lc].get();
      Parts parts;
      const Eigen::VectorXd& force = forces[lc];
      bool converged =
          u.size() == num_dofs_ && newton(force, 1.0, u, solver, factorised, borrowed, parts);
      for (int steps = 1; steps <= kMaxSteps && !converged; steps *= 2) {
        u = Eigen::VectorXd::Zero(num_dofs_);
        converged = true;
        for (int k = 1; k <= steps && converged; ++k)
          converged =
              newton(force, static_cast<double>(k) / steps, u, solver, factorised, nullptr, parts);
      }
      cache.factorised[lc] = factorised ? 1 : 0;
      if (converged) {
        shared.nonlinear_starts[lc] = u;
        shared.linear_starts[lc] = u_linear[lc];
      }
      if (factorised && shared.tangents[lc] != owned_solver) {
        shared.tangents[lc] = owned_solver;
        shared.tangent_free_dofs[lc] = free_dofs_;
      }
      if (!converged)
        throw std::runtime_error("the large-deformation model did not converge for load case " +
                                 std::to_string(l + 1) +
                                 " at the current parameters (Newton with up to " +
                                 std::to_string(kMaxSteps) + " load steps)");
      {
        const std::lock_guard<std::mutex> lock(cache.mutex);
        cache.solutions[lc] = u;
        cache.linear_solutions[lc] = u_linear[lc];
      }

      const Eigen::SparseMatrix<double, Eigen::RowMajor>& h = observations_[lc].operator_;
      Eigen::MatrixXd jac;
      if (with_jacobian) {
        Eigen::MatrixXd du;
        if (need_tangent) {
          // dR/dtheta at fixed u: the linear terms' dK/dtheta u and the nonlinear parts n_k(u)
          // de_k (`parts` hold n_k at the converged u: Newton's last evaluation).
          Eigen::MatrixXd rhs = linear_rhs(dforces[lc], u);
          for (size_t t = 0; t < nn; ++t)
            for (size_t k = 0; k < parts[t].size(); ++k) rhs -= parts[t][k] * de[t][k].transpose();
          du = solve_free(solver, rhs);
        }
        if (w_index >= 0) {
          du = need_tangent ? Eigen::MatrixXd(w * du + (1.0 - w) * du_linear[lc]) : du_linear[lc];
          du.col(w_index) += u - u_linear[lc];
        }
        jac = h * du;
      }
      if (w_index >= 0) u = w * u + (1.0 - w) * u_linear[lc];
      Eigen::VectorXd y = h * u;
      add_offsets(l, theta, with_jacobian, y, jac);
      out.predictions[lc] = std::move(y);
      out.jacobians[lc] = std::move(jac);
      out.displacements[lc] = std::move(u);
    } catch (...) {
      errors[lc] = std::current_exception();
    }
  }
  for (const auto& error : errors)
    if (error) std::rethrow_exception(error);
  return out;
}

}  // namespace isospring::fitting
