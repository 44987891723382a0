// The Pareto set and the budgeted choice of cost/error points (pareto.hpp) on hand-made points
// whose answers are read off by hand.
#include <gtest/gtest.h>

#include <cmath>

#include "isospring/fitting/pareto.hpp"

namespace isospring::fitting {
namespace {

TEST(Pareto, HandMadePointsAreClassifiedAsDrawn) {
  //  error
  //  10 |  a
  //   5 |        b      d
  //   2 |              c        e
  //   1 |                              f
  //     +--1-----2-----4----8----16---32--- cost
  const std::vector<CostError> points = {
      {1, 10},          // a: cheapest: optimal
      {2, 5},           // b: optimal
      {4, 2},           // c: optimal
      {8, 5},           // d: dominated by c (cheaper and better)
      {16, 2},          // e: dominated by c (same error, costlier)
      {32, 1},          // f: the most accurate: optimal
      {4, 2},           // g: equal to c: neither dominates the other, both optimal
      {2, 10},          // h: dominated by a (same error, costlier) and by b
      {NAN, 0},         // i: failed: never optimal, dominates none
      {0.5, INFINITY},  // j: failed likewise
  };
  const std::vector<bool> expected = {true, true, true,  false, false,
                                      true, true, false, false, false};
  EXPECT_EQ(pareto_optimal(points), expected);
}

TEST(Pareto, TheMostAccurateWithinABudgetIsOnTheFront) {
  const std::vector<CostError> points = {{1, 10}, {2, 5}, {4, 2}, {8, 5}, {32, 1}, {3, 2}};
  EXPECT_EQ(most_accurate_within(points, 0.5), -1);  // nothing that cheap
  EXPECT_EQ(most_accurate_within(points, 1), 0);     // budget equal to a cost is within it
  EXPECT_EQ(most_accurate_within(points, 2.5), 1);
  EXPECT_EQ(most_accurate_within(points, 3), 5);   // (3, 2)
  EXPECT_EQ(most_accurate_within(points, 10), 5);  // error tie with (4, 2): the cheaper
  EXPECT_EQ(most_accurate_within(points, 100), 4);
  const std::vector<bool> front = pareto_optimal(points);
  for (double budget : {1.0, 2.5, 3.0, 10.0, 100.0})
    EXPECT_TRUE(front[static_cast<size_t>(most_accurate_within(points, budget))]) << budget;
  EXPECT_EQ(most_accurate_within({{NAN, 1}, {1, NAN}}, 100), -1);
}

TEST(Pareto, EmptyAndSinglePoints) {
  EXPECT_TRUE(pareto_optimal({}).empty());
  EXPECT_EQ(pareto_optimal({{3, 4}}), std::vector<bool>{true});
}

}  // namespace
}  // namespace isospring::fitting
