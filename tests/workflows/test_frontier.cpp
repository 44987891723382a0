// The cost/accuracy frontier (workflows/frontier.hpp) on the [S15] square with the quick
// candidates: one row per offered kind, the Pareto flags are those of fitting::pareto_optimal
// on the rows, the measured step is positive and sits within a stated factor of step_cost's
// estimate, the reduced model's held-out error is at least the model it reduces, and a budget
// between two kinds' estimates makes the generalising calibration (what `calibrate
// --max-step-us` runs; tests/apps/test_calibrate_step_budget.cpp checks the flag reaches it)
// pick the kind the frontier says is the most accurate within that budget. One TEST: one run.
#include <gtest/gtest.h>

#include <cmath>

#include "isospring/analysis/static_solver.hpp"
#include "isospring/fitting/generalising_calibration.hpp"
#include "isospring/fitting/pareto.hpp"
#include "isospring/fitting/thesis_experiments.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/workflows/frontier.hpp"

namespace isospring::workflows {
namespace {

// One frontier run (about 15 s of CPU) serves every check below; CTest runs each TEST in a
// process of its own, so they are one TEST.
FrontierResult square_frontier() {
  FrontierOptions options;
  options.objects = {"square"};
  options.quick = true;
  options.timing_samples = 7;
  for (const FrontierKind& k : frontier_kinds())
    if (k.strain_points <= 2 && !k.volume_terms) options.kinds.push_back(k);
  const io::Progress progress("test", true);
  return run_frontier(options, progress);
}

void check_rows(const FrontierObject& square) {
  EXPECT_EQ(square.name, "square");
  EXPECT_TRUE(square.complete);
  const std::vector<std::string> kinds = {"springs", "springs + strain points 1/dir",
                                          "springs + strain points 2/dir", "reduced"};
  ASSERT_EQ(square.rows.size(), kinds.size());
  for (size_t i = 0; i < kinds.size(); ++i) {
    const FrontierRow& row = square.rows[i];
    EXPECT_EQ(row.kind.name, kinds[i]);
    EXPECT_TRUE(row.failure.empty()) << row.failure;
    EXPECT_GT(row.worst_validation, 0.0) << kinds[i];
    EXPECT_GT(row.worst_fitted, 0.0) << kinds[i];
    EXPECT_FALSE(row.worst_case.empty()) << kinds[i];
    EXPECT_FALSE(row.engines.empty()) << kinds[i];
  }
  // Plain springs go everywhere; strain points only through the runtime (MuJoCo's callback);
  // SOFA refuses them; the reduced model runs in the runtime alone.
  EXPECT_EQ(square.rows[0].engines,
            (std::vector<std::string>{"isospring runtime", "MuJoCo (tendons)", "SOFA"}));
  EXPECT_EQ(square.rows[2].engines,
            (std::vector<std::string>{"isospring runtime", "MuJoCo (tendons + runtime callback)"}));
  EXPECT_EQ(square.rows[3].engines, std::vector<std::string>{"isospring runtime (reduced model)"});
  EXPECT_EQ(square.rows[1].strain_point_terms, 16u);  // 4 x 4 knot spans, 1 point each
  EXPECT_EQ(square.rows[2].strain_point_terms, 64u);
}

void check_pareto(const FrontierObject& square) {
  std::vector<fitting::CostError> points;
  for (const FrontierRow& r : square.rows)
    points.push_back({r.measured_step_us, r.worst_validation});
  const std::vector<bool> front = fitting::pareto_optimal(points);
  bool any = false;
  for (size_t i = 0; i < front.size(); ++i) {
    EXPECT_EQ(square.rows[i].pareto, front[i]) << square.rows[i].kind.name;
    any = any || front[i];
  }
  EXPECT_TRUE(any);
  // The most accurate kind is always on the front.
  size_t best = 0;
  for (size_t i = 1; i < points.size(); ++i)
    if (points[i].error < points[best].error) best = i;
  EXPECT_TRUE(square.rows[best].pareto);
}

// step_cost's estimate sums per-term force costs benchmarked on 10^3-10^5-particle lattices;
// the measured step is a force AND a Jacobian-vector product, which bench_runtime puts at 1.5-1.7
// times a force evaluation, so the measurement should be about 2.5 times the estimate; a model
// of 36 particles adds per-call overhead the large lattices amortise, and the shared machine
// adds noise (CPU time, median). Measured 1.7-1.8 (load average 16). Accepted: between 1 and 5
// times the estimate (2D cell terms: test_frontier_cells.cpp).
void check_step_costs(const FrontierObject& square) {
  for (const FrontierRow& r : square.rows) {
    EXPECT_GT(r.measured_step_us, 0.0) << r.kind.name;
    EXPECT_LE(r.measured_min_us, r.measured_step_us);
    EXPECT_GE(r.measured_max_us, r.measured_step_us);
    if (r.kind.reduced) {
      EXPECT_TRUE(std::isnan(r.estimated_step_us));
      continue;
    }
    const double ratio = r.measured_step_us / r.estimated_step_us;
    EXPECT_GT(ratio, 1.0) << r.kind.name;
    EXPECT_LT(ratio, 5.0) << r.kind.name;
  }
  // More terms cost more, measured as estimated: springs < 1 point < 2 points per direction.
  EXPECT_LT(square.rows[0].measured_step_us, square.rows[1].measured_step_us);
  EXPECT_LT(square.rows[1].measured_step_us, square.rows[2].measured_step_us);
  EXPECT_LT(square.rows[0].estimated_step_us, square.rows[1].estimated_step_us);
  EXPECT_LT(square.rows[1].estimated_step_us, square.rows[2].estimated_step_us);
}

// The reduced model's basis holds the training loads' static responses, so its fitted error
// is the full model's (to round-off); a held-out load is projected, so its error is the full
// model's plus the projection's: never below the full model's by more than round-off on every
// case at once.
void check_reduced(const FrontierObject& square) {
  const FrontierRow& reduced = square.rows.back();
  size_t best = 0;
  for (size_t i = 1; i + 1 < square.rows.size(); ++i)
    if (square.rows[i].worst_validation < square.rows[best].worst_validation) best = i;
  EXPECT_EQ(reduced.reduced_of, square.rows[best].kind.name);
  EXPECT_NEAR(reduced.worst_fitted, square.rows[best].worst_fitted,
              1e-6 * square.rows[best].worst_fitted);
  EXPECT_GE(reduced.worst_validation, square.rows[best].worst_validation * (1 - 1e-9));
  EXPECT_GT(reduced.reduced_basis, 0);
}

void check_budget(const FrontierObject& square) {
  std::vector<fitting::CostError> points;  // the kinds calibrate offers, at the cost it budgets
  for (const FrontierRow& r : square.rows)
    if (!r.kind.reduced) points.push_back({r.estimated_step_us, r.worst_validation});
  ASSERT_EQ(points.size(), 3u);
  // The same suite and candidates as the frontier's quick membranes, every kind offered.
  const fitting::ThesisSuite suite = fitting::thesis_load_suite(fitting::thesis_square());
  fitting::CalibrationSettings settings;
  settings.fit_cases = suite.training;
  settings.holdout_cases = suite.validation;
  settings.max_iterations = 3000;
  settings.field_metrics = false;
  settings.prior_max_iterations = 300;
  for (auto& lc : analysis::solve_static(suite.problem).load_cases)
    settings.reference_displacements.push_back(std::move(lc.displacement));
  fitting::GeneralisationOptions options;
  options.gammas = {0.5, 0.01};
  options.prior_weights = {1e-4};
  options.reaches = {1};
  options.strain_points = {0, 1, 2};
  for (const auto& [below, above] : {std::pair{0, 1}, std::pair{1, 2}}) {
    const double budget = std::sqrt(points[below].cost * points[above].cost);
    const int expected = fitting::most_accurate_within(points, budget);
    ASSERT_GE(expected, 0);
    settings.max_step_us = budget;
    const fitting::GeneralisationResult g =
        fitting::calibrate_for_generalisation(suite.problem, settings, options);
    const fitting::CandidateScore& chosen = g.candidates[static_cast<size_t>(g.chosen)];
    EXPECT_EQ(chosen.strain_points, square.rows[static_cast<size_t>(expected)].kind.strain_points)
        << "budget " << budget << " us";
    EXPECT_NEAR(g.worst_validation, points[static_cast<size_t>(expected)].error,
                1e-6 * points[static_cast<size_t>(expected)].error);
  }
}

// report.json reads back to the same result (so runs of single objects combine into one
// report); NaN cells (the reduced model's estimate) survive as null.
void check_report_round_trip(const FrontierResult& result) {
  const nlohmann::json report = frontier_report_json(result);
  const FrontierResult back = frontier_result_from_json(report, "report.json");
  EXPECT_EQ(frontier_report_json(back)["frontier"], report["frontier"]);
  FrontierResult other = back;
  other.objects[0].name = "circle";
  const FrontierResult combined = combine_frontier_results({back, other, result});
  ASSERT_EQ(combined.objects.size(), 2u);  // the square once (rows merged by kind), the circle
  EXPECT_EQ(combined.objects[0].name, "square");
  EXPECT_EQ(combined.objects[1].name, "circle");
  EXPECT_THROW((void)frontier_result_from_json(nlohmann::json::object(), "x.json"),
               nurbs::InputError);
}

TEST(Frontier, SquareRowsParetoSetStepCostsReducedModelAndBudgetChoice) {
  const FrontierResult result = square_frontier();
  ASSERT_EQ(result.objects.size(), 1u);
  const FrontierObject& square = result.objects[0];
  ASSERT_EQ(square.rows.size(), 4u);  // the helpers index the rows
  {
    SCOPED_TRACE("one row per offered kind, with its engines");
    check_rows(square);
  }
  {
    SCOPED_TRACE("Pareto flags");
    check_pareto(square);
  }
  {
    SCOPED_TRACE("measured step against the estimate");
    check_step_costs(square);
  }
  {
    SCOPED_TRACE("reduced model");
    check_reduced(square);
  }
  {
    SCOPED_TRACE("budget choice");
    check_budget(square);
  }
  {
    SCOPED_TRACE("report.json round trip and combination of runs");
    check_report_round_trip(result);
  }
}

}  // namespace
}  // namespace isospring::workflows
