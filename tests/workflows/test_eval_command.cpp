// The eval use case (eval_command.hpp) on the shipped quarter annulus (radii 1 and 2, u along the
// arc, v radial): points and derivatives against the exact geometry, the text and JSON outputs,
// and every refusal.
#include <gtest/gtest.h>

#include <cmath>

#include "isospring/io/patch_file.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/nurbs/knot_vector.hpp"
#include "isospring/workflows/eval_command.hpp"

namespace isospring::workflows {
using namespace isospring::io;  // the formats the use cases read and write
namespace {

const std::string kAnnulus =
    std::string(ISOSPRING_SOURCE_DIR) + "/examples/patches/quarter_annulus.json";

EvalCommandOptions at(std::vector<std::string> points, bool derivatives) {
  EvalCommandOptions o;
  o.input = "quarter_annulus.json";
  o.at = std::move(points);
  o.derivatives = derivatives;
  return o;
}

TEST(EvalUseCase, PointsAndDerivativesOfTheAnnulus) {
  const auto patches = read_patch_file(kAnnulus);
  const EvalCommandResult r = run_eval(patches, at({"0.5,0", "0,1", "0.3,0.4"}, true));
  ASSERT_EQ(r.points.size(), 3u);
  for (const EvalPoint& p : r.points) {
    SCOPED_TRACE(p.text);
    ASSERT_EQ(p.at.size(), 2u);
    ASSERT_EQ(p.derivatives.size(), 2u);
    // On the circle of radius 1 + v; d/dv is the unit radial direction, d/du tangential.
    EXPECT_NEAR(p.point.norm(), 1.0 + p.at[1], 1e-14);
    EXPECT_NEAR((p.derivatives[1] - p.point.normalized()).norm(), 0.0, 1e-14);
    EXPECT_NEAR(p.derivatives[0].dot(p.point), 0.0, 1e-14);
    EXPECT_EQ(p.point.z(), 0.0);
  }
  EXPECT_NEAR(r.points[0].point.x(), std::sqrt(0.5), 1e-15);  // the arc's middle at radius 1
  EXPECT_EQ(r.points[1].point, Eigen::Vector3d(2, 0, 0));
  // Without --derivs: none evaluated, none printed.
  EXPECT_TRUE(run_eval(patches, at({"0.5,0"}, false)).points[0].derivatives.empty());
}

TEST(EvalUseCase, TextAndJsonAreThePrintedOutputs) {
  const auto patches = read_patch_file(kAnnulus);
  const EvalCommandResult r = run_eval(patches, at({"0.5,0", "0,1"}, true));
  // The program's lines, 17 significant digits (as `isospring eval --derivs` printed them before
  // the use case moved into io).
  EXPECT_EQ(eval_text(r),
            "0.5,0: 0.70710678118654746 0.70710678118654746 0 | du: -1.1715728752538099 "
            "1.1715728752538099 0 | dv: 0.70710678118654768 0.70710678118654768 0\n"
            "0,1: 2 0 0 | du: 0 2.8284271247461903 0 | dv: 1 0 0\n");
  const nlohmann::json j = eval_json(r);
  EXPECT_EQ(j["patch"], 0);
  ASSERT_EQ(j["points"].size(), 2u);
  EXPECT_EQ(j["points"][1]["at"], nlohmann::json({0.0, 1.0}));
  EXPECT_EQ(j["points"][1]["point"], nlohmann::json({2.0, 0.0, 0.0}));
  EXPECT_EQ(j["points"][0]["derivatives"][0][0].get<double>(), r.points[0].derivatives[0].x());
  EXPECT_FALSE(
      eval_json(run_eval(patches, at({"0.5,0"}, false)))["points"][0].contains("derivatives"));
}

TEST(EvalUseCase, RefusesWhatIsNotAPointOfThePatch) {
  const auto patches = read_patch_file(kAnnulus);
  auto message = [&](const EvalCommandOptions& o) {
    try {
      run_eval(patches, o);
    } catch (const nurbs::InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(at({"0.5"}, false)).find("parametric dimension 2, so give 2"),
            std::string::npos);
  EXPECT_NE(message(at({"0.5,2"}, false)).find("lies outside [0.000000, 1.000000] in direction 1"),
            std::string::npos);
  EXPECT_NE(message(at({"abc"}, false)).find("is not a number"), std::string::npos);
  EvalCommandOptions other = at({"0.5,0"}, false);
  other.patch = 3;
  EXPECT_EQ(message(other), "--patch 3: the file has 1 patches (0-based index)");
}

TEST(EvalUseCase, OverflowIsAnErrorNotANumber) {
  // A line from -1.7e308 to 1.7e308: its midpoint is 0, its derivative 3.4e308 overflows.
  const nurbs::Patch line({nurbs::KnotVector(1, {0, 0, 1, 1})},
                          {Eigen::Vector3d(-1.7e308, 0, 0), Eigen::Vector3d(1.7e308, 0, 0)});
  EXPECT_EQ(run_eval({line}, at({"0.5"}, false)).points[0].point, Eigen::Vector3d::Zero());
  try {
    run_eval({line}, at({"0.5"}, true));
    FAIL() << "expected an overflow error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("quarter_annulus.json: patch 0 at 0.5: the point or its "
                                         "derivatives overflow a double"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace isospring::workflows
