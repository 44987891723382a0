// The memory estimate made before refining: its sizes are exact (they match the refined patch
// and the assembled stiffness), so the bound it gives is honest.
#include <gtest/gtest.h>

#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/dof_map.hpp"
#include "isospring/analysis/resource_estimate.hpp"
#include "isospring/geometry/primitives.hpp"
#include "isospring/nurbs/refine.hpp"

namespace isospring::analysis {
namespace {

TEST(ResourceEstimate, RefinedSizeMatchesTheRefinedPatch) {
  const nurbs::Patch annulus = geometry::annulus(1.0, 2.0).front();
  const nurbs::Patch refined = nurbs::k_refine(annulus, {3, 4, 1}, {5, 3, 1});
  const PatchSize size = refined_size(annulus, {3 - annulus.degree(0), 4 - annulus.degree(1), 0},
                                      {0, 0, 0}, {5, 3, 1});
  EXPECT_EQ(size.points[0], refined.num_points(0));
  EXPECT_EQ(size.points[1], refined.num_points(1));
  EXPECT_EQ(size.total_points(), refined.num_points());
  EXPECT_EQ(size.degree[1], 4);
}

TEST(ResourceEstimate, NonzerosBoundTheAssembledStiffness) {
  Problem problem;
  problem.patches = {nurbs::k_refine(geometry::box(1, 1, 1).front(), {2, 2, 2}, {6, 5, 4})};
  problem.material = {1e6, 0.3, 0, 1};
  const DofMap dofs(problem);
  const Eigen::SparseMatrix<double> k = assemble_stiffness(problem, dofs);
  const PatchSize size =
      refined_size(geometry::box(1, 1, 1).front(), {1, 1, 1}, {0, 0, 0}, {6, 5, 4});
  const SolveEstimate e = estimate_static_solve({size}, 3);
  EXPECT_EQ(e.dofs, dofs.num_dofs());
  // (2p+1)^d is the interior coupling, so the count bounds K's upper triangle from above, by
  // less than the boundary's share (here about 2x for a small patch).
  EXPECT_GE(e.nonzeros, static_cast<double>(k.nonZeros()));
  EXPECT_LT(e.nonzeros, 2.5 * static_cast<double>(k.nonZeros()));
  EXPECT_GT(e.bytes, 3 * 12 * static_cast<double>(k.nonZeros()));
}

TEST(ResourceEstimate, AvailableMemoryIsKnownAndFormatted) {
  EXPECT_GT(available_memory_bytes(), 1e6);
  EXPECT_EQ(format_bytes(2.04e15), "2.04 PB");
  EXPECT_EQ(format_bytes(512), "512 B");
}

}  // namespace
}  // namespace isospring::analysis
