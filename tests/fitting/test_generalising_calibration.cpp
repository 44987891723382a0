// Calibration for generalisation on the [S15] square: fitted to the load suite, the
// model must predict [S15]'s own load cases, which it never saw, within [S15]'s published
// FITTED-case error (Table 5.3: 1.14 %e_rms); a per-spring model fitted to S15's single case
// misses the axial pull by ~20 %e_rms (docs/nmsm-results.md, the single-case table).
#include <gtest/gtest.h>

#include <algorithm>

#include "isospring/fitting/generalising_calibration.hpp"
#include "isospring/fitting/thesis_experiments.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::fitting {
namespace {

GeneralisationOptions small_candidate_set() {
  GeneralisationOptions options;
  options.reaches = {2};
  options.gammas = {0.5, 0.1};
  options.prior_weights = {1e-3};
  options.folds = 3;
  options.target_percent_e_rms = 1.14;  // [S15] Table 5.3, square
  return options;
}

TEST(GeneralisingCalibration, SquarePredictsS15LoadsItNeverSawWithinThePublishedFittedError) {
  const ThesisObject square = thesis_square();
  const ThesisSuite suite = thesis_load_suite(square);
  CalibrationSettings settings;
  settings.fit_cases = suite.training;
  settings.holdout_cases = suite.validation;
  settings.field_metrics = false;
  settings.prior_max_iterations = 300;
  const GeneralisationResult g =
      calibrate_for_generalisation(suite.problem, settings, small_candidate_set());

  // None of [S15]'s cases was fitted; each is predicted within the published fitted error.
  int s15_cases = 0;
  for (const auto& e : g.calibration.holdout)
    if (e.id == "fit" || e.id == "fit_points" || e.id == "holdout_x" || e.id == "holdout_v1") {
      ++s15_cases;
      EXPECT_LT(e.control.percent_e_rms, 1.14) << e.id;
    }
  EXPECT_EQ(s15_cases, 4);
  for (const auto& e : g.calibration.fit)
    EXPECT_TRUE(std::find(suite.training.begin(), suite.training.end(), e.id) !=
                suite.training.end())
        << e.id << " was fitted but is not a training case";

  // The chosen candidate is the one with the lowest cross-validated worst error, and the
  // reported worst is the largest over fitted and validation cases.
  for (const auto& c : g.candidates) EXPECT_GE(c.worst, g.candidates[g.chosen].worst);
  double worst = 0.0;
  for (const auto* cases : {&g.calibration.fit, &g.calibration.holdout})
    for (const auto& e : *cases) worst = std::max(worst, e.control.percent_e_rms);
  EXPECT_DOUBLE_EQ(g.worst, worst);
  // A worst case above the target is reported, not hidden.
  const bool warned = std::any_of(g.warnings.begin(), g.warnings.end(), [](const std::string& w) {
    return w.find("exceeds the target") != std::string::npos;
  });
  EXPECT_EQ(warned, g.worst > 1.14);
}

TEST(GeneralisingCalibration, RejectsBadOptions) {
  const ThesisObject square = thesis_square(4, 2);
  CalibrationSettings settings;
  settings.fit_cases = {"fit"};
  settings.holdout_cases = {"holdout_x"};
  GeneralisationOptions options = small_candidate_set();
  EXPECT_THROW(calibrate_for_generalisation(square.problem, settings, options),
               nurbs::InputError);  // 1 training case, 3 folds
  options.gammas.clear();
  EXPECT_THROW(calibrate_for_generalisation(square.problem, settings, options), nurbs::InputError);
}

}  // namespace
}  // namespace isospring::fitting
