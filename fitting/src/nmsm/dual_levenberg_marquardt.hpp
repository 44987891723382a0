#pragma once
// Levenberg-Marquardt for many parameters and few residuals (the per-spring displacement fit:
// 1940 spring stiffnesses, ~650 residuals), with box bounds and an optional Tikhonov prior.
//
// Minimises F(x) = 1/2 |r(x)|^2 + 1/2 w |x - p|^2 subject to lower <= x <= upper. The step
// solves (J^T J + (w + mu) I) d = -g, g = J^T r + w (x - p). With P parameters and m < P
// residuals J^T J has rank <= m, so Ceres' normal equations (P x P, cost P^2 m) are singular
// without the prior and its CGNR iterations crawl (1200 LM iterations from the grouped optimum).
// Here the step comes from the m x m system instead (Woodbury identity, a = w + mu):
//   d = -J^T (a I + J J^T)^-1 r - (w / a) (e - J^T (a I + J J^T)^-1 J e),   e = x - p,
// i.e. the minimum-norm Gauss-Newton step as mu -> 0 and w = 0, exact LM steps at m^2 P cost.
// When P <= m the P x P system is solved directly. Bounds: parameters on a bound whose gradient
// points outwards are frozen for the step (active set), the others are projected onto the box.
// Damping update: Nielsen's rule (mu *= max(1/3, 1 - (2 rho - 1)^3) on success, mu *= nu,
// nu *= 2 on failure), as in Madsen, Nielsen & Tingleff, "Methods for non-linear least squares
// problems" (2004), Algorithm 3.16.
#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

namespace isospring::fitting::detail {

struct BoundedLeastSquares {
  /// r(x) and, when the matrix pointer is not null, J(x) (rows: residuals). Returns false when x
  /// cannot be evaluated (the step is then rejected and shortened).
  std::function<bool(const Eigen::VectorXd& x, Eigen::VectorXd& r, Eigen::MatrixXd* jacobian)>
      evaluate;
  /// Optional: J diag(weight) J^T at the point of the last evaluation with a Jacobian, when the
  /// problem has a cheaper way than the dense product; returns false to fall back to it.
  std::function<bool(const Eigen::VectorXd& weight, Eigen::MatrixXd& gram)> gram;
  /// Optional, dual form only: the system a I + J W J^T restricted to the kept residual rows
  /// `rows` as K^-1 (a K^2 + G) K^-1 with symmetric K, K^2 and G (all rows x rows), when the
  /// problem has that structure (the displacement model's K form); false to use gram instead.
  /// The LM then factorises a K^2 + G (+ the shared-prior term K (J A) C (J A)^T K) per trial
  /// and never forms J W J^T.
  std::function<bool(const Eigen::VectorXd& weight, const std::vector<Eigen::Index>& rows,
                     Eigen::MatrixXd& k, Eigen::MatrixXd& k_squared, Eigen::MatrixXd& g)>
      k_form;
  Eigen::VectorXd lower;  // per parameter; -inf when none
  Eigen::VectorXd upper;  // per parameter; +inf when none
  Eigen::VectorXd prior;  // p (used when prior_weight > 0 and prior_groups is empty)
  /// Non-empty: the prior is not fixed but one free shared value per group (prior_groups[i]: the
  /// group of parameter i), eliminated in closed form: p_i = the mean of x over i's group (the
  /// minimiser of the prior term for given x). The cost is then 1/2 |r|^2 + 1/2 w |(I - P) x|^2
  /// (P: group averaging), gradient J^T r + w (x - P x), prior Hessian w (I - P); the step
  /// handles it exactly (Sherman-Morrison per group inside the Woodbury form, see the .cpp).
  std::vector<int> prior_groups;
  double prior_weight = 0.0;
};

struct DualLmOptions {
  int max_iterations = 200;            // trial steps, accepted or not (as Ceres counts them)
  double function_tolerance = 1e-12;   // converged when an accepted step lowers F by < tol * F
  double gradient_tolerance = 1e-14;   // ... or max |P(x - g) - x| <= tol (projected gradient)
  double parameter_tolerance = 1e-12;  // ... or |d| <= tol (|x| + tol)
  std::function<void(int iteration, double cost)> on_iteration;
};

struct DualLmSummary {
  double initial_cost = 0.0;
  double cost = 0.0;
  int iterations = 0;
  bool converged = false;
  std::string message;
};

/// Runs from x (inside the box; it is projected first) and leaves the best point in x. Throws
/// std::runtime_error when the starting point cannot be evaluated.
DualLmSummary solve_dual_levenberg_marquardt(const BoundedLeastSquares& problem, Eigen::VectorXd& x,
                                             const DualLmOptions& options);

}  // namespace isospring::fitting::detail
