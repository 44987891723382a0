// The case files' refinement ladder for identify's discretisation check, and the level between
// two of its levels: degrees first, then doubled elements; in between, 1.5 x the elements of the
// level below, on a multiple of the exact geometry's spans, and geometry-exact.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "isospring/io/case_file.hpp"
#include "isospring/io/case_refinement_ladder.hpp"

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
  EXPECT_EQ(description, "degree 3,3,3, 3 x 9 x 24 elements");
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

}  // namespace
}  // namespace isospring::io
