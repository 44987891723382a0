// The frontier's 2D cell terms and the combination of runs by kind, on the [S15] square with
// the quick candidates (two kinds: springs, and springs + volume + shear terms per net cell).
// step_cost prices a membrane's cell with bench_runtime's 2D sheets (an area term: 4 Gauss
// points of a bilinear cell, about a tenth of the trilinear volume term's 8), so the measured
// step (force + Jacobian-vector product, 1.5-1.7 times a force evaluation, plus the per-call
// overhead of a 36-particle model) sits between 1 and 5 times the estimate for the cell kind as
// for every other kind; priced as 3D cells it was 0.36-0.56 times. Combining a run of each kind
// gives the run of both: its rows in frontier_kinds() order, the same Pareto flags.
#include <gtest/gtest.h>

#include "isospring/workflows/frontier.hpp"

namespace isospring::workflows {
namespace {

TEST(FrontierCells, MembraneCellTermsPricedAsMeasuredAndRunsCombineByKind) {
  FrontierOptions options;
  options.objects = {"square"};
  options.quick = true;
  options.timing_samples = 7;
  for (const FrontierKind& k : frontier_kinds())
    if (k.name == "springs" || k.name == "springs + volume + shear terms")
      options.kinds.push_back(k);
  ASSERT_EQ(options.kinds.size(), 2u);
  const io::Progress progress("test", true);
  const FrontierResult result = run_frontier(options, progress);
  ASSERT_EQ(result.objects.size(), 1u);
  const FrontierObject& square = result.objects[0];
  ASSERT_EQ(square.rows.size(), 2u);
  const FrontierRow& cells = square.rows[1];
  ASSERT_TRUE(cells.failure.empty()) << cells.failure;
  EXPECT_EQ(cells.cell_volume_terms, 25u);  // 5 x 5 net cells of the 6 x 6 net
  EXPECT_EQ(cells.cell_shear_terms, 25u);
  for (const FrontierRow& r : square.rows) {
    const double ratio = r.measured_step_us / r.estimated_step_us;
    EXPECT_GT(ratio, 1.0) << r.kind.name;
    EXPECT_LT(ratio, 5.0) << r.kind.name;
  }

  // One run per kind, the later listed first: combined, they are the run of both.
  FrontierResult springs = result, with_cells = result;
  springs.objects[0].rows = {square.rows[0]};
  with_cells.objects[0].rows = {square.rows[1]};
  with_cells.objects[0].complete = springs.objects[0].complete = true;
  springs.objects[0].rows[0].pareto = with_cells.objects[0].rows[0].pareto = true;
  const FrontierResult combined = combine_frontier_results({with_cells, springs});
  ASSERT_EQ(combined.objects.size(), 1u);
  ASSERT_EQ(combined.objects[0].rows.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(combined.objects[0].rows[i].kind.name, square.rows[i].kind.name);
    EXPECT_EQ(combined.objects[0].rows[i].pareto, square.rows[i].pareto);
    EXPECT_EQ(combined.objects[0].rows[i].worst_validation, square.rows[i].worst_validation);
  }
  EXPECT_TRUE(combined.objects[0].complete);
  EXPECT_DOUBLE_EQ(combined.objects[0].seconds, 2.0 * square.seconds);
}

}  // namespace
}  // namespace isospring::workflows
