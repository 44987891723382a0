// Box-bounded Levenberg-Marquardt with the step from the smaller of the primal (P x P) and dual
// (m x m) systems.
#include "dual_levenberg_marquardt.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace isospring::fitting::detail {

namespace {

// The prior at x: fixed, or the group means of x (prior_groups).
Eigen::VectorXd prior_at(const BoundedLeastSquares& problem, const Eigen::VectorXd& x) {
  if (problem.prior_groups.empty()) return problem.prior;
  const int groups =
      *std::max_element(problem.prior_groups.begin(), problem.prior_groups.end()) + 1;
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(groups), count = Eigen::VectorXd::Zero(groups);
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    sum[problem.prior_groups[i]] += x[i];
    count[problem.prior_groups[i]] += 1.0;
  }
  Eigen::VectorXd prior(x.size());
  for (Eigen::Index i = 0; i < x.size(); ++i)
    prior[i] = sum[problem.prior_groups[i]] / count[problem.prior_groups[i]];
  return prior;
}

double cost_of(const BoundedLeastSquares& problem, const Eigen::VectorXd& x,
               const Eigen::VectorXd& r) {
  double cost = 0.5 * r.squaredNorm();
  if (problem.prior_weight > 0.0)
    cost += 0.5 * problem.prior_weight * (x - prior_at(problem, x)).squaredNorm();
  return cost;
}

// Free shared prior values (prior_groups) for the current active set. The prior Hessian is
// w (I - P), P the group averaging; restricted to the free parameters F, D = alpha I - w P_FF
// (alpha = w + mu) has per group a rank-one deficit, so by Sherman-Morrison
// alpha D^-1 = T = I + A C A^T, A: free-member indicators, c_a = (w / n_a) / (alpha - w n_aF /
// n_a).
struct SharedPrior {
  const std::vector<int>* group = nullptr;  // null: a fixed prior (D = alpha I, T = I)
  Eigen::VectorXd size, free_size;          // n_a and n_aF
  std::vector<bool> frozen;

  SharedPrior(const BoundedLeastSquares& problem, const std::vector<bool>& frozen_parameters)
      : frozen(frozen_parameters) {
    if (problem.prior_groups.empty() || !(problem.prior_weight > 0.0)) return;
    group = &problem.prior_groups;
    const int groups = *std::max_element(group->begin(), group->end()) + 1;
    size = free_size = Eigen::VectorXd::Zero(groups);
    for (size_t i = 0; i < group->size(); ++i) {
      size[(*group)[i]] += 1.0;
      if (!frozen[i]) free_size[(*group)[i]] += 1.0;
    }
  }
  Eigen::VectorXd c(double w, double alpha) const {
    return (w / size.array()) / (alpha - w * free_size.array() / size.array());
  }
  Eigen::VectorXd free_sums(const Eigen::VectorXd& v) const {
    Eigen::VectorXd sums = Eigen::VectorXd::Zero(size.size());
    for (size_t i = 0; i < group->size(); ++i)
      if (!frozen[i]) sums[(*group)[i]] += v[static_cast<Eigen::Index>(i)];
    return sums;
  }
  Eigen::VectorXd apply_t(const Eigen::VectorXd& v, const Eigen::VectorXd& c) const {
    if (!group) return v;
    const Eigen::VectorXd sums = c.cwiseProduct(free_sums(v));
    Eigen::VectorXd out = v;
    for (size_t i = 0; i < group->size(); ++i)
      if (!frozen[i]) out[static_cast<Eigen::Index>(i)] += sums[(*group)[i]];
    return out;
  }
  // J A: per group, the sum of its free columns.
  Eigen::MatrixXd group_columns(const Eigen::MatrixXd& j) const {
    Eigen::MatrixXd out = Eigen::MatrixXd::Zero(j.rows(), size.size());
    for (size_t i = 0; i < group->size(); ++i)
      if (!frozen[i]) out.col((*group)[i]) += j.col(static_cast<Eigen::Index>(i));
    return out;
  }
  // d^T (I - P) d (fixed prior: d^T d).
  double quadratic(const Eigen::VectorXd& d) const {
    double q = d.squaredNorm();
    if (!group) return q;
    Eigen::VectorXd sums = Eigen::VectorXd::Zero(size.size());
    for (size_t i = 0; i < group->size(); ++i) sums[(*group)[i]] += d[static_cast<Eigen::Index>(i)];
    for (Eigen::Index a = 0; a < sums.size(); ++a) q -= sums[a] * sums[a] / size[a];
    return q;
  }
};

// The dual system in K form (BoundedLeastSquares::k_form): S = K^-1 (a K^2 + G) K^-1.
struct KForm {
  Eigen::MatrixXd k, k_squared, g;
};

// The LM step for damping mu (alpha = w + mu) with the active columns of J (and entries of e)
// zeroed. `gram` is J J^T (dual) or J^T J (primal), without the damping; in the dual form it is
// unused when `k_form` is given. In the dual form `jacobian` and `r` hold only the rows of J that
// are not zero (held nodes add nothing).
// Dual (Woodbury, S = alpha I + J J^T + (J A) C (J A)^T): d = -T J^T S^-1 r - h + T J^T S^-1 J h,
// h = T w e / alpha; the data part has no cancellation. In K form S = K^-1 (alpha K^2 + G +
// (K J A) C (K J A)^T) K^-1, so S^-1 v = K (alpha K^2 + G + ...)^-1 K v.
Eigen::VectorXd lm_step(const Eigen::MatrixXd& jacobian, const Eigen::MatrixXd& gram, bool dual,
                        const Eigen::VectorXd& r, const Eigen::VectorXd& e, double w, double alpha,
                        const SharedPrior& shared, const KForm* k_form) {
  const Eigen::VectorXd c = shared.group ? shared.c(w, alpha) : Eigen::VectorXd();
  if (dual) {
    const Eigen::MatrixXd& j = jacobian;
    const Eigen::MatrixXd ja = shared.group ? shared.group_columns(j) : Eigen::MatrixXd();
    auto step_with = [&](auto&& solve) {
      Eigen::VectorXd d = -shared.apply_t(j.transpose() * solve(r), c);
      if (w > 0.0) {
        const Eigen::VectorXd h = shared.apply_t(w * e, c) / alpha;
        d += -h + shared.apply_t(j.transpose() * solve(Eigen::VectorXd(j * h)), c);
      }
      return d;
    };
    if (k_form) {
      Eigen::MatrixXd system = k_form->g + alpha * k_form->k_squared;
      if (shared.group) {
        const Eigen::MatrixXd kja = k_form->k * ja;
        system += kja * c.asDiagonal() * kja.transpose();
      }
      const Eigen::LLT<Eigen::MatrixXd, Eigen::Lower> llt(system);
      // a K^2 + G inherits K's condition number squared (a stiff per-spring fit can make it
      // ~1e16): each solve is refined against S applied through J, and when its backward error
      // stays above 1e-12 after two refinements the step is redone with the dense S below.
      // |S| <= alpha + |J|_F^2 (+ the prior term) bounds the norm in the backward error.
      double s_norm = alpha + j.squaredNorm();
      if (shared.group) s_norm += (ja * c.cwiseAbs().cwiseSqrt().asDiagonal()).squaredNorm();
      bool accurate = llt.info() == Eigen::Success;
      auto solve = [&](const Eigen::VectorXd& v) {
        Eigen::VectorXd y = k_form->k * llt.solve(Eigen::VectorXd(k_form->k * v));
        for (int pass = 0;; ++pass) {
          Eigen::VectorXd residual = v - alpha * y - j * (j.transpose() * y);
          if (shared.group) residual -= ja * c.cwiseProduct(ja.transpose() * y);
          if (residual.norm() <= 1e-12 * (s_norm * y.norm() + v.norm())) break;
          if (pass == 2) {
            accurate = false;
            break;
          }
          y += k_form->k * llt.solve(Eigen::VectorXd(k_form->k * residual));
        }
        return y;
      };
      if (accurate) {
        const Eigen::VectorXd d = step_with(solve);
        if (accurate && d.allFinite()) return d;
      }
    }
    Eigen::MatrixXd system = gram;
    if (k_form) {  // gram holds only J J^T's diagonal then: form S densely
      system.setZero(j.rows(), j.rows());
      system.selfadjointView<Eigen::Lower>().rankUpdate(j);
    }
    system.diagonal().array() += alpha;
    if (shared.group) system += ja * c.asDiagonal() * ja.transpose();
    const Eigen::LLT<Eigen::MatrixXd, Eigen::Lower> llt(system);
    return step_with([&](const Eigen::VectorXd& v) { return Eigen::VectorXd(llt.solve(v)); });
  }
  Eigen::MatrixXd system = gram;
  system.diagonal().array() += alpha;
  if (shared.group)  // H = J^T J + alpha I - w P_FF
    for (size_t i = 0; i < shared.group->size(); ++i)
      for (size_t k = 0; k < shared.group->size(); ++k)
        if (!shared.frozen[i] && !shared.frozen[k] && (*shared.group)[i] == (*shared.group)[k])
          system(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k)) -=
              w / shared.size[(*shared.group)[i]];
  const Eigen::LLT<Eigen::MatrixXd, Eigen::Lower> llt(system);
  return -llt.solve(Eigen::VectorXd(jacobian.transpose() * r + w * e));
}

}  // namespace

DualLmSummary solve_dual_levenberg_marquardt(const BoundedLeastSquares& problem, Eigen::VectorXd& x,
                                             const DualLmOptions& options) {
  const Eigen::Index p = x.size();
  const double w = problem.prior_weight > 0.0 ? problem.prior_weight : 0.0;
  x = x.cwiseMax(problem.lower).cwiseMin(problem.upper);
  Eigen::VectorXd r, trial_r;
  Eigen::MatrixXd jacobian, spare_jacobian;  // spare: reused for the next Jacobian (no 10 MB
                                             // allocation and page-faulting per iteration)
  if (!problem.evaluate(x, r, &jacobian))
    throw std::runtime_error("calibration: the starting stiffnesses cannot be evaluated");
  const Eigen::Index m = r.size();
  const bool dual = m < p;
  DualLmSummary summary;
  double cost = cost_of(problem, x, r);
  summary.initial_cost = cost;
  auto prior_offset = [&](const Eigen::VectorXd& at) {
    return w > 0.0 ? Eigen::VectorXd(at - prior_at(problem, at)) : Eigen::VectorXd::Zero(p);
  };

  // Per-iteration matrices, kept across iterations: same sizes, so no reallocation (each is
  // MBs, and fresh ones cost page faults on every iteration).
  Eigen::MatrixXd gram, active_jacobian;
  KForm k_form;
  double mu = -1.0, nu = 2.0;
  int iteration = 0;
  summary.message = "maximum number of iterations reached";
  while (iteration < options.max_iterations) {
    Eigen::VectorXd e = prior_offset(x);
    const Eigen::VectorXd gradient = jacobian.transpose() * r + w * e;
    // Active set: on a bound with the gradient pushing outwards; frozen for this step.
    const double tiny = 1e-12;
    Eigen::VectorXd weight = Eigen::VectorXd::Ones(p);
    double projected = 0.0;
    for (Eigen::Index i = 0; i < p; ++i) {
      const bool at_lower = x[i] <= problem.lower[i] + tiny * (1.0 + std::abs(x[i]));
      const bool at_upper = x[i] >= problem.upper[i] - tiny * (1.0 + std::abs(x[i]));
      const double moved =
          std::clamp(x[i] - gradient[i], problem.lower[i], problem.upper[i]) - x[i];
      projected = std::max(projected, std::abs(moved));
      if ((at_lower && gradient[i] > 0.0) || (at_upper && gradient[i] < 0.0)) {
        weight[i] = 0.0;
        e[i] = 0.0;
      }
    }
    std::vector<bool> frozen(static_cast<size_t>(p));
    for (Eigen::Index i = 0; i < p; ++i) frozen[static_cast<size_t>(i)] = weight[i] == 0.0;
    const SharedPrior shared(problem, frozen);
    if (projected <= options.gradient_tolerance) {
      summary.converged = true;
      summary.message = "projected gradient below gradient_tolerance";
      break;
    }
    // The m x m (dual) or P x P (primal) Gram matrix; symmetric, so one triangle is formed.
    // The Jacobian with the frozen columns zeroed: all of it (primal) or only its non-zero rows
    // (dual), gathered in one pass over J (a full copy is 10 MB for the per-spring 6^3 cube).
    Eigen::VectorXd reduced_r;
    std::vector<Eigen::Index> rows;
    bool use_k_form = false;
    if (!dual) {
      active_jacobian = jacobian * weight.asDiagonal();
      gram.setZero(p, p);
      gram.selfadjointView<Eigen::Lower>().rankUpdate(active_jacobian.transpose());
    } else {
      Eigen::VectorXd row_size = Eigen::VectorXd::Zero(m);
      for (Eigen::Index i = 0; i < p; ++i)
        if (weight[i] != 0.0) row_size = row_size.cwiseMax(jacobian.col(i).cwiseAbs());
      for (Eigen::Index i = 0; i < m; ++i)
        if (row_size[i] > 0.0) rows.push_back(i);
      active_jacobian.resize(static_cast<Eigen::Index>(rows.size()), p);
      for (Eigen::Index i = 0; i < p; ++i) {
        if (weight[i] == 0.0)
          active_jacobian.col(i).setZero();
        else
          active_jacobian.col(i) = jacobian.col(i)(rows);
      }
      reduced_r = r(rows);
      use_k_form =
          problem.k_form && problem.k_form(weight, rows, k_form.k, k_form.k_squared, k_form.g);
      if (use_k_form) {
        // Only the diagonal is needed (the first damping): the squared row norms of J.
        gram = active_jacobian.rowwise().squaredNorm().asDiagonal();
      } else if (problem.gram && problem.gram(weight, gram)) {
        gram = Eigen::MatrixXd(gram(rows, rows));
      } else {
        gram.setZero(active_jacobian.rows(), active_jacobian.rows());
        gram.selfadjointView<Eigen::Lower>().rankUpdate(active_jacobian);
      }
    }
    if (mu < 0.0) mu = 1e-4 * std::max(gram.diagonal().maxCoeff(), 1e-300);

    bool accepted = false, done = false;
    while (!accepted && iteration < options.max_iterations) {
      ++iteration;
      const Eigen::VectorXd step =
          dual ? lm_step(active_jacobian, gram, true, reduced_r, e, w, w + mu, shared,
                         use_k_form ? &k_form : nullptr)
               : lm_step(active_jacobian, gram, false, r, e, w, w + mu, shared, nullptr);
      const Eigen::VectorXd trial = (x + step).cwiseMax(problem.lower).cwiseMin(problem.upper);
      const Eigen::VectorXd d = trial - x;
      if (d.norm() <= options.parameter_tolerance * (x.norm() + options.parameter_tolerance)) {
        summary.converged = true;
        summary.message = "step below parameter_tolerance";
        done = true;
        break;
      }
      // Decrease predicted by the Gauss-Newton model of F along the projected step.
      const double predicted =
          -gradient.dot(d) - 0.5 * ((jacobian * d).squaredNorm() + w * shared.quadratic(d));
      double trial_cost = INFINITY;
      if (problem.evaluate(trial, trial_r, nullptr) && trial_r.allFinite())
        trial_cost = cost_of(problem, trial, trial_r);
      const double rho = predicted > 0.0 ? (cost - trial_cost) / predicted : -1.0;
      if (rho > 1e-3 && std::isfinite(trial_cost)) {
        Eigen::VectorXd new_r;
        if (!problem.evaluate(trial, new_r, &spare_jacobian)) {
          mu *= nu;
          nu *= 2.0;
          continue;
        }
        const double decrease = cost - trial_cost;
        x = trial;
        r = std::move(new_r);
        jacobian.swap(spare_jacobian);
        cost = trial_cost;
        mu *= std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * rho - 1.0, 3));
        nu = 2.0;
        accepted = true;
        if (decrease <= options.function_tolerance * (cost + decrease)) {
          summary.converged = true;
          summary.message = "cost change below function_tolerance";
          done = true;
        }
      } else {
        mu *= nu;
        nu *= 2.0;
      }
      if (options.on_iteration) options.on_iteration(iteration, cost);
    }
    if (done) break;
  }
  summary.cost = cost;
  summary.iterations = iteration;
  return summary;
}

}  // namespace isospring::fitting::detail
