// NMSM topology: the published spring counts [S15 Table 5.1 and ch. 4], merging and masses.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "isospring/analysis/assembly.hpp"
#include "isospring/fitting/spring_masses.hpp"
#include "isospring/fitting/spring_mesh.hpp"
#include "isospring/fitting/stiffness_groups.hpp"
#include "isospring/nurbs/error.hpp"
#include "nmsm_test_models.hpp"

namespace isospring::fitting {
namespace {

using testing::grid_problem;

struct CountCase {
  std::vector<int> net;
  long published;
};

TEST(SpringMesh, PublishedSpringCounts) {
  const std::vector<CountCase> cases = {{{6, 6}, 110},     {{9, 9}, 272},     {{5, 5}, 72},
                                        {{6, 6, 6}, 1940}, {{7, 7, 7}, 3258}, {{7, 7, 2}, 673},
                                        {{9, 5, 5}, 2000}, {{9, 10, 3}, 2315}};
  for (const auto& c : cases) {
    const std::vector<double> size(c.net.size(), 2.0);
    const SpringMesh mesh = build_spring_mesh(grid_problem(c.net, size));
    const int n2 = c.net.size() == 3 ? c.net[2] : 1;
    EXPECT_EQ(static_cast<long>(mesh.network.springs.size()), c.published)
        << c.net[0] << "x" << c.net[1];
    EXPECT_EQ(expected_spring_count(c.net[0], c.net[1], n2), c.published);
    EXPECT_EQ(mesh.network.positions.size(), static_cast<size_t>(c.net[0] * c.net[1] * n2));
    EXPECT_TRUE(mesh.warnings.empty());
  }
}

TEST(SpringMesh, RestLengthsAndDirectionsOfASquareCell) {
  const SpringMesh mesh = build_spring_mesh(grid_problem({2, 2}, {2.0, 2.0}));
  ASSERT_EQ(mesh.network.springs.size(), 6u);
  const Grouping groups = group_by_rest_length(mesh.network, 0.01);
  EXPECT_EQ(groups.num_groups(), 2);  // 4 edges of length 2 and 2 diagonals of length 2 sqrt(2)
  for (const auto& s : mesh.network.springs) {
    EXPECT_LT(s.i, s.j);
    const bool diagonal = std::abs(s.rest_length - 2.0 * std::sqrt(2.0)) < 1e-14;
    EXPECT_TRUE(diagonal || std::abs(s.rest_length - 2.0) < 1e-14);
  }
}

// An annulus-like net closed in u: the last column of control points repeats the first.
analysis::Problem closed_ring(int around, int radial) {
  std::vector<Eigen::Vector3d> points;
  for (int j = 0; j < radial; ++j)
    for (int i = 0; i <= around; ++i) {
      const double angle = 2.0 * M_PI * (i % around) / around, r = 1.0 + 0.5 * j;
      points.emplace_back(r * std::cos(angle), r * std::sin(angle), 0.0);
    }
  analysis::Problem problem;
  problem.formulation = analysis::Formulation::kPlaneStress;
  problem.patches.emplace_back(
      std::vector<nurbs::KnotVector>{nurbs::KnotVector::uniform(1, around),
                                     nurbs::KnotVector::uniform(1, radial - 1)},
      points);
  return problem;
}

TEST(SpringMesh, ClosedSeamIsGluedLikeTheAnalysisDofMap) {
  // The analysis glues the u0 and u1 sides of the ring (one node per seam point), so the NMSM
  // does too, with or without merging: a periodic 8 x 3 net with 8*3 ring edges + 8*2 radial
  // edges + 2*8*2 diagonals, the seam's springs once.
  const analysis::Problem ring = closed_ring(8, 3);
  for (bool merge : {false, true}) {
    SpringMeshOptions options;
    options.merge_coincident = merge;
    const SpringMesh mesh = build_spring_mesh(ring, options);
    EXPECT_EQ(mesh.network.positions.size(), 24u);
    EXPECT_EQ(mesh.network.springs.size(), 72u);
    EXPECT_EQ(mesh.particle[0][ring.patches[0].index(8, 1)],
              mesh.particle[0][ring.patches[0].index(0, 1)]);
  }
}

TEST(SpringMesh, MergingJoinsCoincidentPointsTheDofMapKeepsApart) {
  // Two quads touching at one corner only: no interface to glue, but the corner coincides.
  analysis::Problem problem;
  problem.formulation = analysis::Formulation::kPlaneStress;
  const auto k = nurbs::KnotVector::uniform(1, 1);
  problem.patches.emplace_back(
      std::vector<nurbs::KnotVector>{k, k},
      std::vector<Eigen::Vector3d>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}});
  problem.patches.emplace_back(
      std::vector<nurbs::KnotVector>{k, k},
      std::vector<Eigen::Vector3d>{{1, 1, 0}, {2, 1, 0}, {1, 2, 0}, {2, 2, 0}});
  EXPECT_EQ(build_spring_mesh(problem).network.positions.size(), 8u);
  SpringMeshOptions options;
  options.merge_coincident = true;
  const SpringMesh merged = build_spring_mesh(problem, options);
  EXPECT_EQ(merged.network.positions.size(), 7u);
  EXPECT_EQ(merged.network.springs.size(), 12u);
  EXPECT_EQ(merged.particle[0][3], merged.particle[1][0]);
}

TEST(SpringMesh, CollapsedCellsSkipZeroLengthSpringsWithWarning) {
  // A triangle-like patch: the whole v = 0 row collapsed to the origin (as at a disk's centre).
  std::vector<Eigen::Vector3d> points;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) points.emplace_back(j * 1.0, j * (i - 1.0) * 0.5, 0.0);
  analysis::Problem problem;
  problem.formulation = analysis::Formulation::kPlaneStress;
  problem.patches.emplace_back(std::vector<nurbs::KnotVector>{nurbs::KnotVector::uniform(1, 2),
                                                              nurbs::KnotVector::uniform(1, 2)},
                               points);
  const SpringMesh mesh = build_spring_mesh(problem);
  // 2 zero-length edges along the collapsed row; every other pair stays.
  EXPECT_EQ(mesh.network.springs.size(), static_cast<size_t>(expected_spring_count(3, 3) - 2));
  ASSERT_EQ(mesh.warnings.size(), 1u);
  for (const auto& s : mesh.network.springs) EXPECT_GT(s.rest_length, 0.0);
}

TEST(SpringMesh, LumpedMassSumsToDensityTimesVolume) {
  for (MassModel model : {MassModel::kLumpedIga, MassModel::kNetCells}) {
    analysis::Problem problem = grid_problem({5, 4, 3}, {2.0, 1.0, 0.5});
    SpringMesh mesh = build_spring_mesh(problem);
    assign_masses(problem, mesh, model);
    const double total =
        std::accumulate(mesh.network.masses.begin(), mesh.network.masses.end(), 0.0);
    // The control net of a regular-grid block spans the block exactly, so both models give
    // rho * 2 * 1 * 0.5.
    EXPECT_NEAR(total, 1143.0, 1e-9);
    for (double m : mesh.network.masses) EXPECT_GT(m, 0.0);
  }
}

TEST(SpringMesh, NetCellMassesOfAUniformSquareNet) {
  analysis::Problem problem = grid_problem({3, 3}, {2.0, 2.0});
  problem.material.thickness = 0.1;
  SpringMesh mesh = build_spring_mesh(problem);
  assign_masses(problem, mesh, MassModel::kNetCells);
  // 4 cells of area 1: corners get rho t / 4 per cell (1, 2 or 4 cells).
  const double quarter = 1143.0 * 0.1 / 4.0;
  EXPECT_NEAR(mesh.network.masses[0], quarter, 1e-12);
  EXPECT_NEAR(mesh.network.masses[1], 2 * quarter, 1e-12);
  EXPECT_NEAR(mesh.network.masses[4], 4 * quarter, 1e-12);
}

TEST(SpringMesh, GammaGroupingMergesNearbyLengths) {
  analysis::SpringNetwork net;
  for (double length : {1.0, 1.004, 1.3, 2.0, 1.009, 2.05}) {
    analysis::Spring s;
    s.rest_length = length;
    net.springs.push_back(s);
  }
  EXPECT_EQ(group_by_rest_length(net, 0.01).group_of_spring, (std::vector<int>{0, 0, 1, 2, 0, 3}));
  EXPECT_EQ(group_by_rest_length(net, 0.3).num_groups(), 2);
  EXPECT_EQ(group_by_rest_length(net, 0.0).num_groups(), 6);
  EXPECT_THROW(group_by_rest_length(net, 1.5), nurbs::InputError);
}

}  // namespace
}  // namespace isospring::fitting
