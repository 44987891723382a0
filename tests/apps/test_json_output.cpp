// End-to-end: `info --json` and `eval --json` print machine-readable JSON on stdout with values
// checked against closed forms.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "run_program.hpp"

using isospring::testing::example;
using isospring::testing::run_isospring;

// The block part is 0.1 x 0.02 x 0.02 m: one trilinear volume, 6 usable planar faces.
TEST(JsonOutput, InfoOnACadPart) {
  const auto run = run_isospring("info --json " + example("cad/block.step"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json j = nlohmann::json::parse(run.output);
  EXPECT_EQ(j["kind"], "cad");
  EXPECT_EQ(j["cad"]["faces"], 6);
  EXPECT_EQ(j["cad"]["usable_faces"], 6);
  ASSERT_EQ(j["patches"].size(), 1u);
  EXPECT_EQ(j["patches"][0]["degrees"], nlohmann::json({1, 1, 1}));
  EXPECT_NEAR(j["total_measure"].get<double>(), 0.1 * 0.02 * 0.02, 1e-18);
}

// The quarter annulus of radii 1 and 2 (exact rational quadratic arcs): at u = 0.5 on the inner
// arc the point is (cos 45, sin 45) and dX/du is perpendicular to the radius there; (0, 1) is
// the outer arc's start (2, 0).
TEST(JsonOutput, EvalOnTheQuarterAnnulus) {
  const auto run = run_isospring("eval --json --derivs " + example("patches/quarter_annulus.json") +
                                 " --at 0.5,0 --at 0,1");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json j = nlohmann::json::parse(run.output);
  ASSERT_EQ(j["points"].size(), 2u);
  const auto& p = j["points"][0];
  const double c = std::sqrt(0.5);
  EXPECT_NEAR(p["point"][0].get<double>(), c, 1e-15);
  EXPECT_NEAR(p["point"][1].get<double>(), c, 1e-15);
  const double du_x = p["derivatives"][0][0], du_y = p["derivatives"][0][1];
  EXPECT_NEAR(du_x * c + du_y * c, 0.0, 1e-14);                       // tangent of the circle
  EXPECT_NEAR(j["points"][1]["point"][0].get<double>(), 2.0, 1e-15);  // outer radius at u = 0
  EXPECT_NEAR(j["points"][1]["point"][1].get<double>(), 0.0, 1e-15);
}

TEST(JsonOutput, BadParameterIsStillAnInputError) {
  const auto run =
      run_isospring("eval --json " + example("patches/quarter_annulus.json") + " --at 1.5,0");
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_NE(run.output.find("outside"), std::string::npos) << run.output;
}
