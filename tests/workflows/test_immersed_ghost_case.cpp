// The ghost penalty set by a case file ("analysis": {"ghost_fraction": f, "ghost_penalty": g}):
// the values reach the solve (its result reports the fraction used and penalises more faces for a
// larger one), the defaults are ImmersedOptions' own, and a bad value is refused naming the field.
#include <gtest/gtest.h>

#include <string>

#include "immersed_test_parts.hpp"
#include "isospring/analysis/immersed.hpp"
#include "isospring/geometry/immersed_cad.hpp"
#include "isospring/io/immersed_case.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::workflows {
namespace {

io::ImmersedCase octant_case(const testing::ScratchFolder& dir, const nlohmann::json& analysis) {
  testing::write_sphere_octant(dir.path, 1.0, 2.0);
  nlohmann::json j = testing::sphere_octant_case("sphere_octant.step", 1.0, 2.0, 10.0, 4, 2);
  if (!analysis.is_null()) j["analysis"] = analysis;
  return io::read_immersed_case(testing::write_json(dir.path / "octant.json", j));
}

analysis::ImmersedResult solve(const io::ImmersedCase& c) {
  const geometry::ImmersedDomain domain = geometry::immerse_solid(*c.cad, c.immersion);
  return analysis::solve_immersed(domain, io::immersed_options(c, c.load_cases.front()));
}

TEST(ImmersedGhostCase, TheCaseFilesPenaltyReachesTheSolve) {
  const testing::ScratchFolder dir("immersed-ghost-case");
  const io::ImmersedCase plain = octant_case(dir, nullptr);
  EXPECT_EQ(plain.ghost_fraction, analysis::ImmersedOptions{}.ghost_fraction);
  EXPECT_EQ(plain.ghost_penalty, analysis::ImmersedOptions{}.ghost_penalty);
  const io::ImmersedCase wide =
      octant_case(dir, {{"ghost_fraction", 0.3}, {"ghost_penalty", 0.05}});
  const analysis::ImmersedOptions options = io::immersed_options(wide, wide.load_cases.front());
  EXPECT_EQ(options.ghost_fraction, 0.3);
  EXPECT_EQ(options.ghost_penalty, 0.05);

  const analysis::ImmersedResult by_default = solve(plain), widened = solve(wide);
  EXPECT_EQ(by_default.ghost_fraction, analysis::ImmersedOptions{}.ghost_fraction);
  EXPECT_EQ(widened.ghost_fraction, 0.3);
  EXPECT_TRUE(widened.warnings.empty());
  // A larger fraction penalises the faces of more cut cells.
  EXPECT_GT(widened.ghost_faces, by_default.ghost_faces);
}

TEST(ImmersedGhostCase, BadValuesAreRefusedNamingTheField) {
  const testing::ScratchFolder dir("immersed-ghost-case-bad");
  const auto error = [&](const nlohmann::json& analysis) -> std::string {
    try {
      octant_case(dir, analysis);
    } catch (const nurbs::InputError& e) {
      return e.what();
    }
    return "no error";
  };
  const std::string fraction = error({{"ghost_fraction", 1.5}});
  EXPECT_NE(fraction.find("analysis.ghost_fraction"), std::string::npos) << fraction;
  const std::string penalty = error({{"ghost_penalty", -1.0}});
  EXPECT_NE(penalty.find("analysis.ghost_penalty"), std::string::npos) << penalty;
  const std::string unknown = error({{"ghost", 0.1}});
  EXPECT_NE(unknown.find("ghost"), std::string::npos) << unknown;
  EXPECT_NE(unknown, "no error");
}

}  // namespace
}  // namespace isospring::workflows
