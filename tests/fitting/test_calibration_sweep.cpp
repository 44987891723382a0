// Algorithm 5.1 sweep entries: both error measures per gamma, checked against the metrics that
// calibrate() computes independently (error_metrics on a fresh linear solve of the fitted model).
#include <gtest/gtest.h>

#include <algorithm>

#include "isospring/fitting/calibration.hpp"
#include "isospring/fitting/thesis_experiments.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::fitting {
namespace {

TEST(CalibrationSweep, EntriesCarryPercentErmsAndEmaxOfTheirFit) {
  const ThesisObject square = thesis_square(6, 2);
  CalibrationSettings settings;
  settings.fit_cases = {"fit"};
  settings.gamma_sweep = {0.5, 0.01};
  const CalibrationResult result = calibrate(square.problem, settings);
  ASSERT_EQ(result.sweep.size(), 2u);
  for (const SweepEntry& entry : result.sweep) {
    EXPECT_GT(entry.percent_e_max, 0.0);
    // max_i |e_i| >= sqrt(mean |e_i|^2): an identity of the two measures.
    EXPECT_GE(entry.percent_e_max, entry.percent_e_rms);
  }
  const auto kept = std::find_if(result.sweep.begin(), result.sweep.end(),
                                 [&](const SweepEntry& e) { return e.gamma == result.gamma; });
  ASSERT_NE(kept, result.sweep.end());
  // The kept entry comes from the fit's residuals, the metrics from solve_spring_linear on the
  // calibrated network: same quantity, two code paths; agreement to solver round-off.
  EXPECT_NEAR(kept->percent_e_max / result.fit[0].control.percent_e_max, 1.0, 1e-9);
  EXPECT_NEAR(kept->percent_e_rms / result.fit[0].control.percent_e_rms, 1.0, 1e-9);
}

// A per-spring fit given the grouped optimum as its start (per_spring_start, how `isospring
// thesis` reuses its sweep) is the fit that first computes that optimum itself: same start, same
// deterministic iterations, so the same result to round-off. A start of the wrong size is bad
// input.
TEST(CalibrationSweep, PerSpringStartEqualsFittingTheGroupedOptimumFirst) {
  const ThesisObject square = thesis_square(6, 2);
  CalibrationSettings settings;
  settings.fit_cases = {"fit_points"};
  settings.gamma = 0.2;
  const CalibrationResult grouped = calibrate(square.problem, settings);
  settings.per_spring = true;
  settings.regularization = 1e-7;
  const CalibrationResult fitted_first = calibrate(square.problem, settings);
  settings.per_spring_start = grouped.fit_result.spring_stiffness;
  const CalibrationResult given = calibrate(square.problem, settings);
  EXPECT_NEAR(given.fit[0].control.percent_e_rms, fitted_first.fit[0].control.percent_e_rms,
              1e-12 * fitted_first.fit[0].control.percent_e_rms);
  settings.per_spring_start.pop_back();
  EXPECT_THROW(calibrate(square.problem, settings), nurbs::InputError);
}

}  // namespace
}  // namespace isospring::fitting
