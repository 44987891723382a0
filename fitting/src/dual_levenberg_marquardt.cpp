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

double cost_of(const BoundedLeastSquares& problem, const Eigen::VectorXd& x,
               const Eigen::VectorXd& r) {
  double cost = 0.5 * r.squaredNorm();
  if (problem.prior_weight > 0.0)
    cost += 0.5 * problem.prior_weight * (x - problem.prior).squaredNorm();
  return cost;
}

// The LM step for damping a = w + mu with the active columns of J (and entries of e) zeroed.
// `gram` is J J^T (dual) or J^T J (primal), without the damping. In the dual form `jacobian` and
// `r` hold only the rows of J that are not zero (held nodes add nothing to the step).
Eigen::VectorXd lm_step(const Eigen::MatrixXd& jacobian, const Eigen::MatrixXd& gram, bool dual,
                        const Eigen::VectorXd& r, const Eigen::VectorXd& e, double w, double a) {
  Eigen::MatrixXd system = gram;
  system.diagonal().array() += a;
  const Eigen::LLT<Eigen::MatrixXd, Eigen::Lower> llt(system);
  if (dual) {
    const Eigen::MatrixXd& j = jacobian;
    // No cancellation in the data part: -J^T (a I + J J^T)^-1 r.
    Eigen::VectorXd d = -j.transpose() * llt.solve(r);
    if (w > 0.0) d -= (w / a) * (e - j.transpose() * llt.solve(Eigen::VectorXd(j * e)));
    return d;
  }
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
    return w > 0.0 ? Eigen::VectorXd(at - problem.prior) : Eigen::VectorXd::Zero(p);
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
          dual ? lm_step(reduced_jacobian, gram, true, reduced_r, e, w, w + mu)
               : lm_step(active_jacobian, gram, false, r, e, w, w + mu);
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
          -gradient.dot(d) - 0.5 * ((jacobian * d).squaredNorm() + w * d.squaredNorm());
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
