// The case files' refinement ladder for identify's discretisation check, and the level between
// two of its levels: degrees first, then doubled elements; in between, 1.5 x the elements of the
// level below, on a multiple of the exact geometry's spans, and geometry-exact.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "isospring/io/case_file.hpp"
#include "isospring/io/case_refinement_ladder.hpp"
#include "isospring/io/graded_ladder.hpp"

namespace isospring::io {
namespace {

// A tube sector at degree 2 with the given elements (through the wall, around, along the axis);
// its arcs are one rational quadratic span per quarter turn.
Case tube_case(std::array<int, 3> elements, double sweep_degrees = 90.0) {
  const nlohmann::json document = {
      {"geometry",
       {{"type", "tube"},
        {"inner_radius", 0.02},
        {"outer_radius", 0.026},
        {"length", 0.12},
        {"sweep_angle", sweep_degrees}}},
      {"discretization", {{"degree", 2}, {"elements", elements}}},
      {"name", "tube"},
      {"material", {{"E", 2e11}, {"nu", 0.3}}},
      {"boundary", {{{"side", "w0"}, {"fix", {"x", "y", "z"}}}}},
      {"load_cases",
       {{{"id", "pull"}, {"tractions", {{{"side", "w1"}, {"value", {0, 0, 1e6}}}}}}}}};
  return build_case_from_json(document, "case.json");
}

TEST(CaseRefinementLadder, RaisesDegreesThenDoublesElements) {
  const Case c = tube_case({1, 3, 8});
  const CaseDiscretization one = ladder_discretization(c, 1), two = ladder_discretization(c, 2);
  EXPECT_EQ(one.degree, (std::array<int, 3>{3, 3, 3}));
  EXPECT_EQ(one.elements, (std::array<int, 3>{1, 3, 8}));
  EXPECT_EQ(two.degree, (std::array<int, 3>{3, 3, 3}));
  EXPECT_EQ(two.elements, (std::array<int, 3>{2, 6, 16}));
}

TEST(CaseRefinementLadder, IntermediateLevelIsOneAndAHalfTimesTheLevelBelow) {
  const Case c = tube_case({1, 3, 8});
  // Level 1 raises the degree: nothing lies between it and the case's own level.
  EXPECT_FALSE(intermediate_discretization(c, 1).has_value());
  const std::optional<CaseDiscretization> between = intermediate_discretization(c, 2);
  ASSERT_TRUE(between.has_value());
  EXPECT_EQ(between->degree, (std::array<int, 3>{3, 3, 3}));
  // 1 -> 2 (1.5 rounded up), 3 -> 5, 8 -> 12.
  EXPECT_EQ(between->elements, (std::array<int, 3>{2, 5, 12}));
  const std::optional<CaseDiscretization> three = intermediate_discretization(c, 3);
  ASSERT_TRUE(three.has_value());
  EXPECT_EQ(three->elements, (std::array<int, 3>{3, 9, 24}));

  // The problem is built on it, geometry-exact: the tube's points stay on their radii.
  std::string description;
  const std::optional<analysis::Problem> problem = case_refinement_intermediate(c)(3, &description);
  ASSERT_TRUE(problem.has_value());
  // Clamped at w0: graded nets (graded_ladder.hpp), still on the tube's radii.
  EXPECT_EQ(description, "degree 3,3,3, 3 x 9 x 24 elements, graded towards the clamp (w0)");
  const nurbs::Patch& patch = problem->patches.at(0);
  for (int d = 0; d < 3; ++d) EXPECT_EQ(patch.degree(d), 3);
  for (double u : {0.0, 0.37, 1.0})
    for (double w : {0.0, 0.61, 1.0}) {
      const Eigen::Vector3d x = patch.point(nurbs::Param{u, 0.5, w});
      const double radius = std::hypot(x.x(), x.y());
      EXPECT_GE(radius, 0.02 - 1e-12);
      EXPECT_LE(radius, 0.026 + 1e-12);
    }
}

TEST(CaseRefinementLadder, IntermediateElementsStayOnTheGeometrysSpans) {
  // A full ring is 4 spans around: 1.5 x 4 = 6 is not a multiple of 4, so that direction goes to
  // 8, as on the next level; the other directions still lie between.
  const Case c = tube_case({1, 4, 3}, 360.0);
  const std::optional<CaseDiscretization> between = intermediate_discretization(c, 2);
  ASSERT_TRUE(between.has_value());
  EXPECT_EQ(between->elements, (std::array<int, 3>{2, 8, 5}));
  EXPECT_NO_THROW(problem_at(c, *between));
}

// The suite's cantilever: a box clamped at u0.
Case box_case(const nlohmann::json& boundary, const std::string& loaded = "u1") {
  const nlohmann::json document = {
      {"geometry", {{"type", "box"}, {"size", {0.1, 0.02, 0.02}}}},
      {"discretization", {{"degree", 2}, {"elements", {10, 2, 2}}}},
      {"name", "cantilever"},
      {"material", {{"E", 7.5e6}, {"nu", 0.49}}},
      {"boundary", boundary},
      {"load_cases",
       {{{"id", "down"}, {"tractions", {{{"side", loaded}, {"value", {0, 0, -2000}}}}}}}}};
  return build_case_from_json(document, "case.json");
}

TEST(GradedLadder, ClampedBoxIsGradedTowardsTheClampAndItsEdges) {
  const Case c = box_case({{{"side", "u0"}, {"fix", {"x", "y", "z"}}}});
  const std::optional<ClampGrading> grading = clamp_grading(c);
  ASSERT_TRUE(grading.has_value());
  EXPECT_EQ(grading->label, "graded towards the clamp (u0)");
  std::string description;
  const std::optional<analysis::Problem> level = case_refinement_ladder(c)(2, &description);
  ASSERT_TRUE(level.has_value());
  EXPECT_EQ(description, "degree 3,3,3, 20 x 4 x 4 elements, graded towards the clamp (u0)");
  const nurbs::Patch& patch = level->patches.at(0);
  // Breakpoints: (i / 20)^2 along u from the clamp, 0.5 (2i / 4)^2 and its mirror across.
  const std::vector<double> u = patch.knots(0).unique(), v = patch.knots(1).unique();
  ASSERT_EQ(u.size(), 21u);
  for (int i = 0; i <= 20; ++i) EXPECT_NEAR(u[static_cast<size_t>(i)], i * i / 400.0, 1e-15);
  ASSERT_EQ(v.size(), 5u);
  EXPECT_NEAR(v[1], 0.125, 1e-15);
  EXPECT_NEAR(v[2], 0.5, 1e-15);
  EXPECT_NEAR(v[3], 0.875, 1e-15);
  EXPECT_EQ(patch.knots(2).unique(), v);
  // Same DOFs as the uniform net of level 2 and the same geometry: the box's affine map.
  EXPECT_EQ(patch.num_points(), problem_at(c, ladder_discretization(c, 2)).patches[0].num_points());
  for (double a : {0.0, 0.013, 0.5, 1.0})
    for (double b : {0.0, 0.21, 1.0}) {
      const Eigen::Vector3d x = patch.point(nurbs::Param{a, b, 1.0 - b});
      EXPECT_LT((x - Eigen::Vector3d(0.1 * a, 0.02 * b, 0.02 * (1.0 - b))).norm(), 1e-16);
    }
  // The clamp and the load are where the case puts them.
  ASSERT_EQ(level->supports.size(), 1u);
  EXPECT_EQ(analysis::side_name(level->supports[0].side), "u0");
  ASSERT_EQ(level->load_cases.size(), 1u);
  // The level between 10 x 2 x 2 and 20 x 4 x 4 is graded too.
  const std::optional<analysis::Problem> between = case_refinement_intermediate(c)(3, &description);
  ASSERT_TRUE(between.has_value());
  EXPECT_EQ(description, "degree 3,3,3, 30 x 6 x 6 elements, graded towards the clamp (u0)");
  EXPECT_NEAR(between->patches[0].knots(0).unique()[1], 1.0 / 900.0, 1e-15);
}

TEST(GradedLadder, OnlyClampedSolidsAreGraded) {
  // Pinned in one direction only, or a symmetry plane: no clamp, uniform nets.
  EXPECT_FALSE(clamp_grading(box_case({{{"side", "u0"}, {"fix", {"x"}}}})).has_value());
  EXPECT_FALSE(clamp_grading(box_case({{{"side", "u0"}, {"symmetry", true}}})).has_value());
  std::string description;
  ASSERT_TRUE(
      case_refinement_ladder(box_case({{{"side", "u0"}, {"fix", {"x"}}}}))(2, &description));
  EXPECT_EQ(description, "degree 3,3,3, 20 x 4 x 4 elements");
  // Clamped at both ends: graded towards both.
  const std::optional<ClampGrading> both = clamp_grading(box_case(
      {{{"side", "u0"}, {"fix", {"x", "y", "z"}}}, {{"side", "u1"}, {"fix", {"x", "y", "z"}}}},
      "w1"));
  ASSERT_TRUE(both.has_value());
  EXPECT_TRUE(both->directions[0].towards_start && both->directions[0].towards_end);
  EXPECT_EQ(both->label, "graded towards the clamp (u0, u1)");
}

TEST(GradedLadder, AFullRingIsNotGradedAroundItsSeam) {
  const Case c = tube_case({1, 4, 4}, 360.0);
  const std::optional<ClampGrading> grading = clamp_grading(c);
  ASSERT_TRUE(grading.has_value());
  EXPECT_TRUE(grading->directions[0].graded());   // through the wall: towards both surfaces
  EXPECT_FALSE(grading->directions[1].graded());  // around: one seam, no edge
  EXPECT_TRUE(grading->directions[2].towards_start && !grading->directions[2].towards_end);
  const analysis::Problem level = graded_problem_at(c, ladder_discretization(c, 2), *grading);
  const nurbs::Patch& patch = level.patches.at(0);
  EXPECT_EQ(patch.knots(1).num_elements(), 8);
  for (double u : {0.0, 0.3, 1.0})
    for (double v : {0.1, 0.45, 0.8})
      for (double w : {0.0, 0.02, 1.0}) {
        const Eigen::Vector3d x = patch.point(nurbs::Param{u, v, w});
        const double radius = std::hypot(x.x(), x.y());
        EXPECT_NEAR(radius, 0.02 + 0.006 * u, 1e-14);
        EXPECT_NEAR(x.z(), 0.12 * w, 1e-14);
      }
}

}  // namespace
}  // namespace isospring::io
