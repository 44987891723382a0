// The load suite: which sides it loads, how it splits training and validation, and
// that every case deforms the part (a case that loads nothing would make the fit meaningless).
#include <gtest/gtest.h>

#include <algorithm>

#include "isospring/analysis/static_solver.hpp"
#include "isospring/fitting/load_suite.hpp"
#include "isospring/fitting/thesis_experiments.hpp"
#include "isospring/nurbs/error.hpp"
#include "nmsm_test_models.hpp"

namespace isospring::fitting {
namespace {

bool has(const std::vector<std::string>& ids, const std::string& id) {
  return std::find(ids.begin(), ids.end(), id) != ids.end();
}

TEST(LoadSuite, MembraneLoadsEveryFreeSideAndValidatesOnOtherDistributions) {
  const analysis::Problem square = testing::grid_problem({5, 5}, {2, 2});  // u0 fixed
  const LoadSuite suite = generate_load_suite(square, {});
  // Training: 3 free sides x (x, y, twist) + self-weight along x and y; the fixed side u0 is not
  // loaded. Validation: a ramp per free side and oblique self-weight.
  ASSERT_EQ(suite.cases.size(), 15u);
  for (const auto& lc : suite.cases) EXPECT_EQ(lc.id.find("u0"), std::string::npos) << lc.id;
  EXPECT_EQ(suite.validation, (std::vector<std::string>{"p0_u1_ramp", "p0_v0_ramp", "p0_v1_ramp",
                                                        "gravity_oblique"}));
  EXPECT_EQ(suite.training.size(), 11u);
  for (const auto& id : suite.validation) EXPECT_FALSE(has(suite.training, id));

  analysis::Problem loaded = square;
  loaded.load_cases = suite.cases;
  for (const auto& lc : analysis::solve_static(loaded).load_cases)
    EXPECT_GT(lc.displacement.norm(), 0.0) << lc.id;
}

// The spheroid's w0 is its axis (collapsed) and v0, v1 its held poles: only the cut faces u1 and
// the outer surfaces w1 of both patches are loaded.
TEST(LoadSuite, SolidSkipsSupportedAndCollapsedSides) {
  const ThesisObject spheroid = thesis_coupled_spheroid();
  const LoadSuite suite = generate_load_suite(spheroid.problem, {});
  EXPECT_EQ(suite.cases.size(), 4u * 5u + 4u);
  for (const std::string side : {"p0_u1", "p0_w1", "p1_u1", "p1_w1"}) {
    for (const std::string kind : {"_x", "_y", "_z", "_twist"})
      EXPECT_TRUE(has(suite.training, side + kind)) << side + kind;
    EXPECT_TRUE(has(suite.validation, side + "_ramp")) << side;
  }
  EXPECT_EQ(suite.validation.size(), 5u);
}

TEST(LoadSuite, RejectsNothingToLoad) {
  analysis::Problem square = testing::grid_problem({4, 4}, {1, 1});
  LoadSuiteOptions options;
  options.axis_tractions = options.twists = options.self_weight = options.validation = false;
  EXPECT_THROW(generate_load_suite(square, options), nurbs::InputError);
}

}  // namespace
}  // namespace isospring::fitting
