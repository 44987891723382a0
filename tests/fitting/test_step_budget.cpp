// A budget per engine step (CalibrationSettings::max_step_us, step_cost.hpp): cross-validation
// picks the most accurate model kind within it. On the [S15] square with its load suite, strain
// points (2 per direction) predict far better than plain springs (docs/calibration.md: best
// cross-validated worst 0.42 against 3.12) and cost more per step; a budget between the two
// estimates must leave the strain points out and choose the springs, no budget the points. A
// plain calibration over the budget is refused before any fit.
#include <gtest/gtest.h>

#include <string>

#include "isospring/fitting/generalising_calibration.hpp"
#include "isospring/fitting/spring_mesh.hpp"
#include "isospring/fitting/step_cost.hpp"
#include "isospring/fitting/thesis_experiments.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::fitting {
namespace {

double step_us(const analysis::Problem& problem, int strain_points) {
  SpringMeshOptions mesh;
  mesh.strain_points = strain_points;
  return estimated_step_us(build_spring_mesh(problem, mesh).network);
}

TEST(StepBudget, CrossValidationPicksTheMostAccurateKindWithinTheBudget) {
  const ThesisSuite suite = thesis_load_suite(thesis_square());
  CalibrationSettings settings;
  settings.fit_cases = suite.training;
  settings.holdout_cases = suite.validation;
  settings.field_metrics = false;
  GeneralisationOptions options;
  options.gammas = {0.5};
  options.prior_weights = {};
  options.strain_points = {0, 2};
  const double springs = step_us(suite.problem, 0), points = step_us(suite.problem, 2);
  ASSERT_LT(springs, points);

  const GeneralisationResult free = calibrate_for_generalisation(suite.problem, settings, options);
  EXPECT_EQ(free.candidates[static_cast<size_t>(free.chosen)].strain_points, 2);

  settings.max_step_us = 0.5 * (springs + points);
  const GeneralisationResult budget =
      calibrate_for_generalisation(suite.problem, settings, options);
  const CandidateScore& chosen = budget.candidates[static_cast<size_t>(budget.chosen)];
  EXPECT_EQ(chosen.strain_points, 0);
  EXPECT_LE(chosen.estimated_step_us, settings.max_step_us);
  EXPECT_GT(budget.worst, free.worst);  // the price of the budget, in accuracy
  for (const CandidateScore& c : budget.candidates)
    if (c.strain_points == 2) {
      EXPECT_NE(c.failure.find("over the budget"), std::string::npos) << c.failure;
      EXPECT_NEAR(c.estimated_step_us, points, 1e-12 * points);
    }
}

TEST(StepBudget, PlainCalibrationOverTheBudgetIsRefused) {
  const ThesisObject square = thesis_square();
  CalibrationSettings settings;
  settings.fit_cases = {"fit_points"};
  settings.max_step_us = 0.5 * step_us(square.problem, 0);
  try {
    (void)calibrate(square.problem, settings);
    FAIL() << "a model over the budget was calibrated";
  } catch (const nurbs::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("max_step_us"), std::string::npos) << e.what();
  }
  settings.max_step_us = 2.0 * step_us(square.problem, 0);
  EXPECT_NO_THROW((void)calibrate(square.problem, settings));
}

}  // namespace
}  // namespace isospring::fitting
