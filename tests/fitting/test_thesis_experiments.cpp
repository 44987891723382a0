// [S15] Table 5.3 square membrane against the IGA reference (protocol: thesis_experiments.hpp).
// Published: 1.14 / 2.79 (%e_rms / %e_max, 2 groups, simulated annealing).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/dof_map.hpp"
#include "isospring/analysis/spring_static.hpp"
#include "isospring/analysis/static_solver.hpp"
#include "isospring/fitting/calibration.hpp"
#include "isospring/fitting/spring_mesh.hpp"
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

// A per-spring fit starts at the grouped optimum and Levenberg-Marquardt only accepts steps that
// lower the cost, so it can never end worse. The circle's 18 groups span more than 1e6 in
// stiffness: a lower bound relative to the largest start once moved the smallest groups up and
// the fit ended at 49 % against the grouped 4.6 % (measured now: 2.77 % vs 4.58 %).
TEST(ThesisExperiments, PerSpringFitNeverEndsAboveItsGroupedStart) {
  const ThesisObject circle = thesis_circle();
  CalibrationSettings settings;
  settings.fit_cases = {"fit_points"};
  settings.holdout_cases = circle.holdout_cases;
  settings.max_iterations = 3000;
  settings.gamma = 0.001;
  const CalibrationResult grouped = calibrate(circle.problem, settings);
  settings.per_spring = true;
  settings.regularization = 1e-7;
  const CalibrationResult per_spring = calibrate(circle.problem, settings);
  EXPECT_LE(per_spring.fit[0].control.percent_e_rms,
            grouped.fit[0].control.percent_e_rms * (1 + 1e-9));
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

// Is the square's grouped 2.55 %e_rms (published 1.14) an optimizer gap or the protocol? With 2
// groups the objective depends on the scale s and the ratio r = k_diagonal / k_edge only, and
// for fixed r the best scale is a closed-form projection (u scales as 1/s). A scan over r from
// 1e-3 to 1e3 (4001 log-spaced values, so neighbouring ratios differ by 0.35 %) with that scale
// therefore bounds the global minimum from above: Levenberg-Marquardt must be at or below it.
// The scan recomputes the errors independently of the fit (IGA reference from solve_static, loads
// from assemble_load, spring solves from solve_spring_linear); it first reproduces the fit's own
// error at the fitted stiffnesses to 1e-9, which checks that reconstruction.
TEST(ThesisExperiments, SquareTwoGroupFitIsTheGlobalOptimum) {
  const ThesisObject square = thesis_square(6, 2);
  CalibrationSettings settings;
  settings.fit_cases = {"fit_points"};
  const CalibrationResult result = calibrate(square.problem, settings);
  ASSERT_EQ(result.parameters, 2);
  const analysis::DofMap dofs(square.problem);
  const analysis::SpringNetwork& network = result.mesh.network;
  ASSERT_EQ(static_cast<size_t>(dofs.num_nodes()), network.positions.size());  // nothing merged
  size_t c = 0;
  while (square.problem.load_cases[c].id != "fit_points") ++c;
  const Eigen::VectorXd force =
      analysis::assemble_load(square.problem, dofs, square.problem.load_cases[c]);
  const Eigen::VectorXd reference =
      analysis::solve_static(square.problem).load_cases[c].displacement;
  const int dim = dofs.dofs_per_node();
  double o_max = 0.0;
  for (int a = 0; a < dofs.num_nodes(); ++a)
    o_max = std::max(o_max, reference.segment(a * dim, dim).norm());
  auto percent_rms = [&](const Eigen::VectorXd& u) {
    return 100.0 * std::sqrt((u - reference).squaredNorm() / dofs.num_nodes()) / o_max;
  };
  EXPECT_NEAR(percent_rms(analysis::solve_spring_linear(network, force).displacement),
              result.fit[0].control.percent_e_rms, 1e-9 * result.fit[0].control.percent_e_rms);

  double best = INFINITY;
  for (int i = 0; i <= 4000; ++i) {
    const double ratio = std::pow(10.0, -3.0 + 6.0 * i / 4000.0);
    analysis::SpringNetwork trial = network;
    for (auto& s : trial.springs) s.stiffness = s.group == 0 ? 1.0 : ratio;
    const Eigen::VectorXd u = analysis::solve_spring_linear(trial, force).displacement;
    const double scale = u.dot(reference) / u.squaredNorm();  // best 1/s for this ratio
    best = std::min(best, percent_rms(scale * u));
  }
  // Measured: fit 2.548957, scan 2.548966 (a grid can only be at or above the optimum).
  EXPECT_LE(result.fit[0].control.percent_e_rms, best * (1 + 1e-6));
  EXPECT_GT(result.fit[0].control.percent_e_rms, 0.999 * best);
}

// Per-spring fits from several grouped starts (as `isospring thesis` runs them): the per-spring
// objective is not convex, and on the ellipse the best end point does not come from the best
// grouping (29 groups at gamma 0.01 -> 2.51 %e_rms) but from a coarser one. Measured with the
// starts gamma 0.2 and 0.01: 1.57 / 4.20, below the published 2.44 / 6.67.
TEST(ThesisExperiments, EllipsePerSpringFromSeveralStartsIsBelowPublished) {
  const ThesisObject ellipse = thesis_ellipse();
  CalibrationSettings settings;
  settings.fit_cases = {"fit_points"};
  settings.holdout_cases = ellipse.holdout_cases;
  settings.max_iterations = 3000;
  settings.per_spring = true;
  settings.regularization = 1e-7;
  settings.gamma_sweep = {0.2, 0.01};
  const CalibrationResult result = calibrate(ellipse.problem, settings);
  EXPECT_EQ(result.parameters, 110);
  EXPECT_LE(result.fit[0].control.percent_e_rms, ellipse.published_e_rms);
  EXPECT_LE(result.fit[0].control.percent_e_max, ellipse.published_e_max);
  for (const auto& s : result.mesh.network.springs)
    EXPECT_TRUE(s.stiffness > 0.0 && std::isfinite(s.stiffness));
  ASSERT_EQ(result.holdout.size(), 2u);
  for (const auto& h : result.holdout) EXPECT_TRUE(std::isfinite(h.control.percent_e_rms));
}

// The four curved objects of Table 5.1: spring counts against published-results.md, every load
// case scaled to %eps_G = 10, and a grouped fit (one gamma) with finite errors on every case.
TEST(ThesisExperiments, CurvedObjectsMatchPublishedNetsAndReportFiniteErrors) {
  // [S15] Table 5.1 counts are the closed-form counts of the unmerged nets.
  EXPECT_EQ(expected_spring_count(6, 6), 110);
  EXPECT_EQ(expected_spring_count(9, 5, 5), 2000);
  EXPECT_EQ(expected_spring_count(9, 10, 3), 2315);
  for (const std::string name : {"circle", "ellipse", "torus", "coupled_spheroid"}) {
    SCOPED_TRACE(name);
    const ThesisObject object = thesis_object(name);
    const SpringMesh mesh = build_spring_mesh(object.problem);
    if (name == "coupled_spheroid") {
      // Two 9x5x3 nets (2 x 1070 springs) instead of S15's stacked 9x10x3 one: the 175 springs
      // between the stacked nets join coincident poles (zero length), and the collapsed poles and
      // axis leave 544 zero-length pairs that cannot be springs (measured: 1596 remain).
      EXPECT_EQ(object.published_springs, 2315);
      EXPECT_EQ(2 * expected_spring_count(9, 5, 3), 2140);
      EXPECT_EQ(mesh.network.springs.size(), 1596u);
    } else {
      // Unmerged nets (the torus seam is open): exactly S15's count.
      EXPECT_EQ(static_cast<long>(mesh.network.springs.size()), object.published_springs);
    }
    // The factor was bisected on the unscaled solution; a fresh IGA solve of the scaled problem
    // (linear: displacements scale exactly) must give 10 to solver round-off.
    for (double eps : deformation_percent(object.problem)) EXPECT_NEAR(eps, 10.0, 1e-6);
    CalibrationSettings settings;
    settings.fit_cases = {"fit_points"};
    settings.holdout_cases = object.holdout_cases;
    // The gamma `isospring thesis` selects for each object (other gammas can drive groups to the
    // lower bound and leave a singular network, which calibrate reports as an error).
    settings.gamma = name == "circle"    ? 0.001
                     : name == "ellipse" ? 0.01
                     : name == "torus"   ? 0.5
                                         : 0.1;
    settings.max_iterations = 3000;
    // A fit that leaves the network numerically singular is reported with the object's name.
    CalibrationResult result;
    try {
      result = calibrate(object.problem, settings);
    } catch (const std::exception& e) {
      ADD_FAILURE() << name << ": " << e.what();
      continue;
    }
    ASSERT_EQ(result.fit.size(), 1u);
    ASSERT_EQ(result.holdout.size(), 2u);
    EXPECT_TRUE(std::isfinite(result.fit[0].control.percent_e_rms));
    EXPECT_GT(result.fit[0].control.percent_e_rms, 0.0);
    for (const auto& h : result.holdout) EXPECT_TRUE(std::isfinite(h.control.percent_e_rms));
  }
}

}  // namespace
}  // namespace isospring::fitting
