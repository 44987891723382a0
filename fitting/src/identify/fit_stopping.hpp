#pragma once
// The stopping rule of the measured-data loop's fits on the absolute decrease of the weighted RSS.
//
// Every fit of the loop weights its residuals by 1 / sigma, so its RSS is in units of the noise
// variance and its Gauss-Newton covariance is (J^T J)^-1. A fit whose last accepted step lowered
// the RSS by less than `negligible_rss` and whose full Gauss-Newton step from the new point
// predicts less than that again (|P_J r|^2, the projection of the residual on the Jacobian's
// columns) has nothing left that any decision of the loop could see:
//  - the F statistics, (RSS_0 - RSS_1 - allowance) / d1 / (RSS_1 / d2) with RSS_1 / d2 near 1,
//    move by about negligible_rss / d1, and BIC's n ln(RSS_1 / RSS_0) by about negligible_rss,
//    while under the null hypothesis the reduction a candidate's d1 parameters buy is chi^2(d1)
//    distributed, with a standard deviation sqrt(2 d1) >= 1.4 (the statistic's own resolution);
//  - the predicted reduction is delta^T J^T J delta for the step delta to the linearised optimum,
//    the square of its length in standard errors: 1e-3 leaves the parameters within
//    sqrt(1e-3) = 0.032 standard errors (jointly) of where the fit would end.
// Ceres' own rule is relative (function_tolerance 1e-10 of the cost): with thousands of rows it
// keeps walking along a flat valley, where every evaluation factorises K once the stiffness has
// parameters beyond E (a stiffness gradient the data do not contain took 11 iterations, the last
// six each gaining less than 1e-4 of the cost).
#include <ceres/iteration_callback.h>

#include <Eigen/Core>
#include <limits>

namespace isospring::fitting::identify_loop {

// The loop's threshold, in units of the noise variance (see above).
inline constexpr double kNegligibleRss = 1e-3;

// The RSS reduction of the full Gauss-Newton step for the weighted Jacobian `jacobian` and the
// weighted residual `residual` (measured minus predicted): |P_J r|^2. Columns are scaled to unit
// norm first (the projection does not depend on their scale, the rank decision does: E ratios of
// order one beside rotations of 1e-5); zero columns (held parameters' partners) drop out.
double gauss_newton_reduction(const Eigen::MatrixXd& jacobian, const Eigen::VectorXd& residual);

// What a fit's cost function reports to the stopping rule: the predicted reduction at the last
// point where the Jacobian was evaluated, which in Ceres' trust-region loop is the last accepted
// point when the iteration callback runs.
struct FitProgress {
  double predicted_reduction = std::numeric_limits<double>::infinity();
  bool stopped = false;  // the rule ended the fit
};

// Ends a fit (successfully) after an accepted step that lowered the RSS by less than
// `negligible_rss` when the Gauss-Newton prediction from the new point is below it too; never
// at iteration 0 (no step yet) nor after a rejected step. negligible_rss <= 0: never.
class NegligibleDecreaseStop : public ceres::IterationCallback {
 public:
  NegligibleDecreaseStop(double negligible_rss, FitProgress& progress)
      : negligible_rss_(negligible_rss), progress_(progress) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& summary) override {
    if (!(negligible_rss_ > 0.0) || summary.iteration == 0 || !summary.step_is_successful)
      return ceres::SOLVER_CONTINUE;
    // Ceres' cost is half the RSS.
    if (2.0 * summary.cost_change < negligible_rss_ &&
        progress_.predicted_reduction < negligible_rss_) {
      progress_.stopped = true;
      return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
    }
    return ceres::SOLVER_CONTINUE;
  }

 private:
  double negligible_rss_;
  FitProgress& progress_;
};

}  // namespace isospring::fitting::identify_loop
