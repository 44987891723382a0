// A solve whose loads or results overflow a double fails (std::runtime_error: exit status 3)
// naming the load case, instead of returning inf/NaN that reports would write as null.
#include <gtest/gtest.h>

#include <stdexcept>

#include "isospring/analysis/static_solver.hpp"
#include "isospring/geometry/primitives.hpp"
#include "isospring/nurbs/refine.hpp"

namespace isospring::analysis {
namespace {

// A clamped 0.1 x 0.02 x 0.02 m box, degree 2, 2 x 1 x 1 elements, pulled down on its free end.
Problem cantilever(double youngs_modulus, double traction, double density, double gravity) {
  Problem problem;
  problem.patches = {nurbs::k_refine(geometry::box(0.1, 0.02, 0.02).front(), {2, 2, 2}, {2, 1, 1})};
  problem.material = {youngs_modulus, 0.3, density, 1.0};
  Support clamp;
  clamp.side = parse_side("u0");
  clamp.fixed = {true, true, true};
  problem.supports = {clamp};
  LoadCase load;
  load.id = "tip";
  Traction t;
  t.side = parse_side("u1");
  t.value = {0, 0, -traction};
  if (traction != 0) load.tractions = {t};
  load.gravity = {0, 0, -gravity};
  problem.load_cases = {load};
  return problem;
}

std::string failure(const Problem& problem) {
  try {
    solve_static(problem);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "solved";
}

TEST(FiniteResults, AnOrdinaryCaseSolves) {
  EXPECT_EQ(failure(cantilever(5e4, 100, 0, 0)), "solved");
}

TEST(FiniteResults, AnOverflowingTractionNamesTheLoadCase) {
  const std::string message = failure(cantilever(5e4, 1e308, 0, 0));
  EXPECT_NE(message.find("load case 'tip'"), std::string::npos) << message;
  EXPECT_NE(message.find("overflowed"), std::string::npos) << message;
}

TEST(FiniteResults, AnOverflowingSelfWeightNamesTheLoadVector) {
  const std::string message = failure(cantilever(5e4, 0, 1e308, 9.81));
  EXPECT_NE(message.find("load case 'tip': the load vector overflowed"), std::string::npos)
      << message;
}

TEST(FiniteResults, ATinyModulusNamesTheDisplacements) {
  const std::string message = failure(cantilever(1e-300, 100, 0, 0));
  EXPECT_NE(message.find("load case 'tip'"), std::string::npos) << message;
  EXPECT_NE(message.find("displacement"), std::string::npos) << message;
  EXPECT_NE(message.find("E = 1e-300 Pa"), std::string::npos) << message;
}

}  // namespace
}  // namespace isospring::analysis
