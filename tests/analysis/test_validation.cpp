// Bad input ends in nurbs::InputError with a message that says what and where.
#include <gtest/gtest.h>

#include "analysis_models.hpp"
#include "isospring/analysis/static_solver.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::analysis {
namespace {

Problem good_beam() {
  Problem problem;
  problem.formulation = Formulation::kPlaneStress;
  problem.material = {1000.0, 0.3, 1.0, 1.0};
  problem.patches.push_back(testing::beam(4.0, 1.0, 2, 4, 1));
  Support clamp;
  clamp.side = {0, 0, 0};
  clamp.fixed = {true, true, false};
  problem.supports.push_back(clamp);
  LoadCase load;
  load.id = "tip";
  Traction t;
  t.side = {0, 0, 1};
  t.value = {0, -1, 0};
  load.tractions.push_back(t);
  problem.load_cases.push_back(load);
  return problem;
}

// Runs solve_static and returns the InputError message ("" when none was thrown).
std::string input_error(const Problem& problem) {
  try {
    solve_static(problem);
  } catch (const nurbs::InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Validation, GoodProblemSolves) {
  EXPECT_EQ(input_error(good_beam()), "");
}

TEST(Validation, MaterialRanges) {
  Problem p = good_beam();
  p.material.youngs_modulus = 0.0;
  EXPECT_NE(input_error(p).find("youngs_modulus"), std::string::npos);
  p = good_beam();
  p.material.poisson_ratio = 0.5;
  EXPECT_NE(input_error(p).find("poisson_ratio"), std::string::npos);
  p.material.poisson_ratio = -1.0;
  EXPECT_NE(input_error(p).find("poisson_ratio"), std::string::npos);
}

TEST(Validation, SidesPatchesAndLoadCases) {
  Problem p = good_beam();
  p.supports[0].side = {0, 2, 0};  // w0 on a surface
  EXPECT_NE(input_error(p).find("side w0 does not exist on patch 0"), std::string::npos);
  p = good_beam();
  p.load_cases[0].tractions[0].side.patch = 3;
  EXPECT_NE(input_error(p).find("patch 3 does not exist"), std::string::npos);
  p = good_beam();
  p.load_cases.clear();
  EXPECT_NE(input_error(p).find("no load cases"), std::string::npos);
  p = good_beam();
  p.load_cases[0].tractions[0].side = {0, 0, 0};  // the clamped side
  EXPECT_NE(input_error(p).find("every displacement component of this side is fixed"),
            std::string::npos);
  p = good_beam();
  p.load_cases[0].point_loads.push_back({0, 999, {1, 0, 0}});
  EXPECT_NE(input_error(p).find("control point 999 does not exist"), std::string::npos);
  EXPECT_THROW(parse_side("x1"), nurbs::InputError);
  EXPECT_EQ(side_name(parse_side("w1", 2)), "w1");
}

TEST(Validation, RigidBodyModesAreNamed) {
  Problem p = good_beam();
  p.supports[0].fixed = {true, false, false};  // only u_x on the left end
  EXPECT_EQ(input_error(p).find("the supports leave free: translation y"), 0u) << input_error(p);
  p.supports[0].control_point = 0;  // one corner fixed in x and y: rotation stays free
  p.supports[0].fixed = {true, true, false};
  EXPECT_NE(input_error(p).find("rotation about z"), std::string::npos) << input_error(p);
  // 3D: a volume with no supports at all.
  Problem solid;
  solid.material = {1.0, 0.3, 1.0, 1.0};
  solid.patches.push_back(testing::sphere_octant(1.0, 2.0));
  LoadCase load;
  load.id = "gravity";
  load.gravity = {0, 0, -9.81};
  solid.load_cases.push_back(load);
  EXPECT_NE(input_error(solid).find("translation x, translation y, translation z, rotation about "
                                    "x, rotation about y, rotation about z"),
            std::string::npos)
      << input_error(solid);
}

// Two beams end to end: with the same knots across the shared end they are glued and solve;
// with different ones (2 elements across against 1) the ends lie on each other but share no
// control points, which would let the beams come apart there: a named input error.
TEST(Validation, NonConformingInterfaceIsNamed) {
  auto shifted_beam = [](int ny) {
    nurbs::Patch beam = testing::beam(4.0, 1.0, 2, 4, ny);
    for (int i = 0; i < beam.num_points(); ++i)
      beam.set_control_point(i, beam.control_point(i) + Eigen::Vector3d(4, 0, 0));
    return beam;
  };
  Problem p = good_beam();
  p.patches.push_back(shifted_beam(1));
  p.load_cases[0].tractions[0].side = {1, 0, 1};
  EXPECT_EQ(input_error(p), "");
  p.patches[1] = shifted_beam(2);
  EXPECT_EQ(input_error(p).find("patch 0 side u1 and patch 1 side u0 lie on each other but their "
                                "control points differ"),
            0u)
      << input_error(p);
}

TEST(Validation, InvertedPatchIsReportedWithElementAndParameter) {
  Problem p = good_beam();
  // Mirror the net in y: the parametrisation becomes left-handed (det J < 0).
  std::vector<Eigen::Vector3d> points = p.patches[0].control_points();
  for (auto& x : points) x.y() = -x.y();
  p.patches[0] = nurbs::Patch(p.patches[0].all_knots(), points, p.patches[0].weights());
  const std::string message = input_error(p);
  EXPECT_NE(message.find("patch 0, element 0: the Jacobian determinant is"), std::string::npos)
      << message;
  EXPECT_NE(message.find("at parameter ("), std::string::npos);
}

TEST(Validation, SymmetryNeedsAnAxisAlignedSide) {
  Problem p;
  p.formulation = Formulation::kPlaneStrain;
  p.material = {1.0, 0.3, 1.0, 1.0};
  p.patches.push_back(testing::quarter_ring());
  Support s;
  s.side = {0, 0, 0};  // the inner arc
  s.symmetry = true;
  p.supports.push_back(s);
  LoadCase load;
  load.id = "p";
  load.pressures.push_back({{0, 0, 1}, 1.0});
  p.load_cases.push_back(load);
  EXPECT_NE(input_error(p).find("normal to a coordinate axis"), std::string::npos);
}

}  // namespace
}  // namespace isospring::analysis
