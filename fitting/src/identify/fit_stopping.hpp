#pragma once
// The stopping rule of the measured-data loop's fits on the absolute decrease of the weighted RSS.
//
// Every fit of the loop weights its residuals by 1 / sigma, and its tests read RSS differences in
// units of the residual variance s^2 = RSS / (rows - parameters): the F statistic is
// (RSS_0 - RSS_1 - allowance) / d1 / s^2, the standard errors of a candidate's parameters are
// scaled by s, BIC's n ln(RSS_1 / RSS_0) moves by about (RSS_1 - RSS_0) / s^2. s^2 is near 1
// once the model explains the data and far above it while effects are missing (a round-1
// candidate fitted on a residual 500 times the noise variance). A fit whose last accepted step
// lowered the RSS by less than `negligible` s^2 and whose full Gauss-Newton step from the new
// point predicts less than that again (|P_J r|^2, the projection of the residual on the
// Jacobian's columns) has nothing left that a decision of the loop could see:
//  - the F statistics move by about negligible / d1 and BIC by about negligible, while under the
//    null hypothesis the reduction a candidate's d1 parameters buy is s^2 chi^2(d1), with a
//    standard deviation of sqrt(2 d1) >= 1.4 s^2 (the statistic's own resolution);
//  - the predicted reduction is delta^T J^T J delta for the step delta to the linearised optimum,
//    s^2 times the square of its length in standard errors: 1e-3 leaves the parameters within
//    sqrt(1e-3) = 0.032 standard errors (jointly) of where the fit would end.
// Ceres' own rule is relative (function_tolerance 1e-10 of the cost, which is (rows / 2) s^2):
// it ends a fit on a trial step (a factorisation once the stiffness has parameters beyond E)
// whose decrease is 1e-10 n / 2 s^2, so that with thousands of rows it keeps walking along a
// flat valley long after the decreases stopped mattering.
#include <ceres/iteration_callback.h>

#include <Eigen/Core>
#include <limits>

namespace isospring::fitting::identify_loop {

// The loop's threshold, in units of the residual variance (see above).
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
// `negligible` s^2 when the Gauss-Newton prediction from the new point is below it too, where
// s^2 = RSS / `degrees_of_freedom` at the new point; never at iteration 0 (no step yet) nor
// after a rejected step. negligible <= 0 or no degrees of freedom: never.
class NegligibleDecreaseStop : public ceres::IterationCallback {
 public:
  NegligibleDecreaseStop(double negligible, int degrees_of_freedom, FitProgress& progress)
      : negligible_(negligible), degrees_of_freedom_(degrees_of_freedom), progress_(progress) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& summary) override {
    if (!(negligible_ > 0.0) || degrees_of_freedom_ <= 0 || summary.iteration == 0 ||
        !summary.step_is_successful)
      return ceres::SOLVER_CONTINUE;
    // Ceres' cost is half the RSS.
    const double limit = negligible_ * 2.0 * summary.cost / degrees_of_freedom_;
    if (2.0 * summary.cost_change < limit && progress_.predicted_reduction < limit) {
      progress_.stopped = true;
      return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
    }
    return ceres::SOLVER_CONTINUE;
  }

 private:
  double negligible_;
  int degrees_of_freedom_;
  FitProgress& progress_;
};

}  // namespace isospring::fitting::identify_loop
