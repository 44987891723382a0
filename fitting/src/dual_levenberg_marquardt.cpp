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

// The LM step for damping mu (alpha = w + mu) with the active columns of J (and entries of e)
// zeroed. `gram` is J J^T (dual) or J^T J (primal), without the damping. In the dual form
// `jacobian` and `r` hold only the rows of J that are not zero (held nodes add nothing).
// Dual (Woodbury, S = alpha I + J J^T + (J A) C (J A)^T): d = -T J^T S^-1 r - h + T J^T S^-1 J h,
// h = T w e / alpha; the data part has no cancellation.
Eigen::VectorXd lm_step(const Eigen::MatrixXd& jacobian, const Eigen::MatrixXd& gram, bool dual,
                        const Eigen::VectorXd& r, const Eigen::VectorXd& e, double w, double alpha,
                        const SharedPrior& shared) {
  Eigen::MatrixXd system = gram;
  system.diagonal().array() += alpha;
  const Eigen::VectorXd c = shared.group ? shared.c(w, alpha) : Eigen::VectorXd();
  if (dual) {
    const Eigen::MatrixXd& j = jacobian;
    if (shared.group) {
      const Eigen::MatrixXd ja = shared.group_columns(j);
      system += ja * c.asDiagonal() * ja.transpose();
    }
    const Eigen::LLT<Eigen::MatrixXd, Eigen::Lower> llt(system);
    Eigen::VectorXd d = -shared.apply_t(j.transpose() * llt.solve(r), c);
    if (w > 0.0) {
      const Eigen::VectorXd h = shared.apply_t(w * e, c) / alpha;
      d += -h + shared.apply_t(j.transpose() * llt.solve(Eigen::VectorXd(j * h)), c);
    }
    return d;
  }
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
  Eigen::MatrixXd jacobian;
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

  double mu = -1.0, nu = 2.0;
  int iteration = 0;
  summary.message = "maximum number of iterations reached";
  while (iteration < options.max_iterations) {
    Eigen::VectorXd e = prior_offset(x);
    const Eigen::VectorXd gradient = jacobian.transpose() * r + w * e;
    // Active set: on a bound with the gradient pushing outwards; frozen for this step.
    const double tiny = 1e-12;
    Eigen::MatrixXd active_jacobian = jacobian;
    Eigen::VectorXd weight = Eigen::VectorXd::Ones(p);
    double projected = 0.0;
    for (Eigen::Index i = 0; i < p; ++i) {
      const bool at_lower = x[i] <= problem.lower[i] + tiny * (1.0 + std::abs(x[i]));
      const bool at_upper = x[i] >= problem.upper[i] - tiny * (1.0 + std::abs(x[i]));
      const double moved =
          std::clamp(x[i] - gradient[i], problem.lower[i], problem.upper[i]) - x[i];
      projected = std::max(projected, std::abs(moved));
      if ((at_lower && gradient[i] > 0.0) || (at_upper && gradient[i] < 0.0)) {
        active_jacobian.col(i).setZero();
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
    Eigen::MatrixXd gram, reduced_jacobian;
    Eigen::VectorXd reduced_r;
    std::vector<Eigen::Index> rows;
    if (!dual) {
      gram.setZero(p, p);
      gram.selfadjointView<Eigen::Lower>().rankUpdate(active_jacobian.transpose());
    } else {
      for (Eigen::Index i = 0; i < m; ++i)
        if (active_jacobian.row(i).cwiseAbs().maxCoeff() > 0.0) rows.push_back(i);
      reduced_jacobian = active_jacobian(rows, Eigen::all);
      reduced_r = r(rows);
      if (problem.gram && problem.gram(weight, gram)) {
        gram = Eigen::MatrixXd(gram(rows, rows));
      } else {
        gram.setZero(reduced_jacobian.rows(), reduced_jacobian.rows());
        gram.selfadjointView<Eigen::Lower>().rankUpdate(reduced_jacobian);
      }
    }
    if (mu < 0.0) mu = 1e-4 * std::max(gram.diagonal().maxCoeff(), 1e-300);

    bool accepted = false, done = false;
    while (!accepted && iteration < options.max_iterations) {
      ++iteration;
      const Eigen::VectorXd step =
          dual ? lm_step(reduced_jacobian, gram, true, reduced_r, e, w, w + mu, shared)
               : lm_step(active_jacobian, gram, false, r, e, w, w + mu, shared);
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
        Eigen::MatrixXd new_jacobian;
        if (!problem.evaluate(trial, new_r, &new_jacobian)) {
          mu *= nu;
          nu *= 2.0;
          continue;
        }
        const double decrease = cost - trial_cost;
        x = trial;
        r = std::move(new_r);
        jacobian = std::move(new_jacobian);
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
