// The measured-data loop's fits: the stopping rule on the absolute RSS decrease (in units of the
// residual variance, fit_stopping.hpp) and the hold-out refits that start from the final model's
// factor. Uses the loop's private stages (fitting/src/identify).
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <iostream>
#include <random>

#include "identify/fit_stopping.hpp"
#include "identify/loop_state.hpp"
#include "isospring/fitting/effect.hpp"
#include "isospring/fitting/identify.hpp"
#include "test_identify_plate.hpp"

namespace isospring::fitting::identify_loop {
namespace {

using testing::add_noise;
using testing::grid_markers;
using testing::plate_problem;

// An iteration with RSS `rss` after a step that lowered it by `rss_decrease`.
ceres::IterationSummary step(int iteration, bool successful, double rss_decrease,
                             double rss = 100.0) {
  ceres::IterationSummary summary;
  summary.iteration = iteration;
  summary.step_is_successful = successful;
  summary.cost = 0.5 * rss;  // Ceres' cost is half the RSS
  summary.cost_change = 0.5 * rss_decrease;
  return summary;
}

// 100 rows of unit noise (RSS 100 on 100 degrees of freedom): s^2 = 1, the limit 1e-3.
TEST(FitStopping, EndsOnlyWhenTheDecreaseAndItsPredictionAreBothNegligible) {
  FitProgress progress;
  NegligibleDecreaseStop stop(1e-3, 100, progress);
  progress.predicted_reduction = 0.9e-3;
  EXPECT_EQ(stop(step(4, true, 1.1e-3)), ceres::SOLVER_CONTINUE);  // the step still gained
  EXPECT_FALSE(progress.stopped);
  EXPECT_EQ(stop(step(0, true, 0.0)), ceres::SOLVER_CONTINUE);   // no step yet
  EXPECT_EQ(stop(step(4, false, 0.0)), ceres::SOLVER_CONTINUE);  // a rejected step
  progress.predicted_reduction = 1.1e-3;                         // more is still predicted
  EXPECT_EQ(stop(step(4, true, 0.5e-3)), ceres::SOLVER_CONTINUE);
  EXPECT_FALSE(progress.stopped);
  progress.predicted_reduction = 0.9e-3;
  EXPECT_EQ(stop(step(4, true, 0.5e-3)), ceres::SOLVER_TERMINATE_SUCCESSFULLY);
  EXPECT_TRUE(progress.stopped);
  FitProgress off_progress;
  off_progress.predicted_reduction = 0.0;
  NegligibleDecreaseStop off(0.0, 100, off_progress);  // the rule switched off
  EXPECT_EQ(off(step(4, true, 0.0)), ceres::SOLVER_CONTINUE);
  NegligibleDecreaseStop no_dof(1e-3, 0, off_progress);  // as many parameters as rows
  EXPECT_EQ(no_dof(step(4, true, 0.0)), ceres::SOLVER_CONTINUE);
}

// The limit scales with the residual variance: with RSS 50,000 on 100 degrees of freedom (a
// model missing effects, s^2 = 500) a decrease of 0.4 noise variances is negligible, 0.6 not.
TEST(FitStopping, LimitIsInUnitsOfTheResidualVariance) {
  FitProgress progress;
  NegligibleDecreaseStop stop(1e-3, 100, progress);
  progress.predicted_reduction = 0.4;
  EXPECT_EQ(stop(step(4, true, 0.6, 5e4)), ceres::SOLVER_CONTINUE);
  EXPECT_EQ(stop(step(4, true, 0.4, 5e4)), ceres::SOLVER_TERMINATE_SUCCESSFULLY);
}

// |P_J r|^2 against a residual built with a known projection: r = J c + e with e orthogonal to
// J's columns, so the reduction is |J c|^2, whatever the scales of the columns.
TEST(FitStopping, GaussNewtonReductionIsTheProjectionOnTheJacobian) {
  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  Eigen::MatrixXd j(40, 4);
  for (Eigen::Index k = 0; k < j.size(); ++k) j.data()[k] = normal(rng);
  j.col(1) *= 1e-5;  // a rotation beside a relative modulus
  j.col(3) *= 1e4;
  Eigen::VectorXd e(40);
  for (Eigen::Index k = 0; k < e.size(); ++k) e[k] = normal(rng);
  e -= j * (j.transpose() * j).ldlt().solve(j.transpose() * e);
  const Eigen::Vector4d c(0.3, -2e4, 1.0, 5e-5);
  const Eigen::VectorXd r = j * c + e;
  const double expected = (j * c).squaredNorm();
  EXPECT_NEAR(gauss_newton_reduction(j, r), expected, 1e-9 * expected);
  EXPECT_NEAR(gauss_newton_reduction(j, e), 0.0, 1e-9 * e.squaredNorm());
  // A zero column (a parameter without effect) changes nothing.
  Eigen::MatrixXd with_zero(40, 5);
  with_zero << j, Eigen::VectorXd::Zero(40);
  EXPECT_NEAR(gauss_newton_reduction(with_zero, r), expected, 1e-9 * expected);
}

// The plate of test_identify_plate.hpp with a graded modulus E (1 + a . (x - x_c) / L): markers
// simulated with a known a and noise of 0.2 % of the largest displacement, the loop's setup on
// them and its stiffness_gradient effect.
struct GradedPlate {
  analysis::Problem problem = plate_problem(16, 6);
  std::vector<Marker> markers = grid_markers(problem);
  Eigen::Vector2d truth{0.5, -0.3};
  double sigma = 0.0;
  Setup setup;
  std::unique_ptr<Effect> gradient;

  GradedPlate() {
    const PlacementResult placed = place_markers(problem.patches, markers, 1e-9);
    const auto clean =
        simulate_markers(problem, markers, placed.placements, {{"stiffness_gradient", truth}});
    double largest = 0.0;
    for (const auto& u : clean) largest = std::max(largest, u.cwiseAbs().maxCoeff());
    sigma = 2e-3 * largest;
    add_noise(markers, clean, sigma, 11);
    make_setup(setup, problem, markers, placed.placements, false, nullptr);
    std::string why;
    gradient = make_effect("stiffness_gradient", setup.context, &why);
  }
  std::vector<Eigen::VectorXd> weights(bool even_markers_only = false) const {
    std::vector<bool> use(markers.size(), true);
    if (even_markers_only)
      for (size_t m = 0; m < use.size(); ++m) use[m] = m % 2 == 0;
    return make_weights(setup, sigma, use);
  }
  // The gradient's fit from a = 0 on a cache of its own, with the rule at `negligible_rss`.
  Fit fit(double negligible_rss, long* factorizations, Eigen::MatrixXd* covariance = nullptr) {
    setup.negligible_rss = negligible_rss;
    const auto cache = make_factorization_cache();
    const Model model = build_model(setup, {gradient.get()}, Eigen::VectorXd::Ones(1), cache);
    const Fit out = run_fit(setup, model, weights(), covariance, FitStart::kNewParameters);
    *factorizations = factorization_stats(*cache).factorizations;
    return out;
  }
};

// The rule ends the gradient's fit earlier than Ceres' relative tolerance (1e-10 of the cost),
// where the RSS is within the threshold of the converged fit's and the parameters within
// sqrt(threshold) standard errors of it (the predicted reduction is their squared distance in
// standard errors); the converged fit finds the simulated gradient to its standard errors.
TEST(FitStopping, GradedPlateStopsEarlyAtTheOptimumToItsStandardError) {
  GradedPlate plate;
  long converged_factorizations = 0, stopped_factorizations = 0;
  Eigen::MatrixXd covariance;
  const Fit converged = plate.fit(0.0, &converged_factorizations, &covariance);
  const Fit stopped = plate.fit(kNegligibleRss, &stopped_factorizations);
  ASSERT_TRUE(converged.ok) << converged.message;
  ASSERT_TRUE(stopped.ok) << stopped.message;
  EXPECT_FALSE(converged.stopped_negligible);
  EXPECT_TRUE(stopped.stopped_negligible) << stopped.message;
  // Ceres' relative rule ends on a trial point (a factorisation) whose decrease is below it; the
  // absolute rule ends on the accepted point before it, or earlier.
  EXPECT_LE(stopped.iterations, converged.iterations);
  EXPECT_LT(stopped_factorizations, converged_factorizations);
  std::cout << "iterations " << stopped.iterations << " / " << converged.iterations
            << ", factorisations " << stopped_factorizations << " / " << converged_factorizations
            << "\n";
  EXPECT_GE(stopped.rss, converged.rss - 1e-9 * converged.rss);
  EXPECT_LT(stopped.rss - converged.rss, kNegligibleRss);
  const Eigen::VectorXd d = stopped.theta - converged.theta;
  EXPECT_LT(d.dot(covariance.ldlt().solve(d)), kNegligibleRss);
  // Against the simulated values: (E ratio 1, a) within 3 standard errors each.
  Eigen::Vector3d expected(1.0, plate.truth[0], plate.truth[1]);
  for (int k = 0; k < 3; ++k)
    EXPECT_LT(std::abs(converged.theta[k] - expected[k]), 3.0 * std::sqrt(covariance(k, k)))
        << "parameter " << k;
  // The rows are 1 / sigma-weighted: the RSS is chi^2 with rows - 3 degrees of freedom.
  EXPECT_NEAR(converged.rss / (converged.rows - 3), 1.0, 5.0 * std::sqrt(2.0 / converged.rows));
}

// A hold-out refit starts from the final fit and copies the loop's factor at it: its first
// evaluation solves without factorising, and the refit under the fold's weights (every other
// marker) ends in a few steps, one factorisation per new point at most.
TEST(FitStopping, HoldoutRefitStartsOnTheFinalModelsFactor) {
  GradedPlate plate;
  plate.setup.negligible_rss = kNegligibleRss;
  Selection selection;
  selection.chosen = {plate.gradient.get()};
  selection.current = build_model(plate.setup, selection.chosen, Eigen::VectorXd::Ones(1));
  selection.current_fit =
      run_fit(plate.setup, selection.current, plate.weights(), nullptr, FitStart::kNewParameters);
  ASSERT_TRUE(selection.current_fit.ok);
  // Something else factorised last (the nominal model), as can happen before the folds.
  const Model nominal = build_model(plate.setup, {}, Eigen::VectorXd::Ones(1));
  (void)nominal.forward->evaluate(Eigen::VectorXd::Ones(1), false);

  factor_final_model(selection);
  const auto fold_cache = copy_factorization_cache(*plate.setup.factorizations);
  const Model fold_model =
      build_model(plate.setup, selection.chosen, selection.current_fit.theta, fold_cache);
  (void)fold_model.forward->evaluate(selection.current_fit.theta, true);
  FactorizationStats first = factorization_stats(*fold_cache);
  EXPECT_EQ(first.factorizations, 0);
  EXPECT_EQ(first.reuses, 1);

  const Fit refit = run_fit(plate.setup, fold_model, plate.weights(true));
  ASSERT_TRUE(refit.ok) << refit.message;
  EXPECT_LE(refit.iterations, 4);
  const FactorizationStats after = factorization_stats(*fold_cache);
  EXPECT_LE(after.factorizations, refit.iterations + 1);
  // The same optimum as a fold's refit from a = 0 (within the rule's resolution).
  plate.setup.negligible_rss = 0.0;
  const Model fresh = build_model(plate.setup, selection.chosen, Eigen::VectorXd::Ones(1),
                                  make_factorization_cache());
  Eigen::MatrixXd covariance;
  const Fit reference =
      run_fit(plate.setup, fresh, plate.weights(true), &covariance, FitStart::kNewParameters);
  ASSERT_TRUE(reference.ok);
  const Eigen::VectorXd d = refit.theta - reference.theta;
  EXPECT_LT(d.dot(covariance.ldlt().solve(d)), kNegligibleRss);
  EXPECT_LT(refit.rss - reference.rss, kNegligibleRss);
}

}  // namespace
}  // namespace isospring::fitting::identify_loop
