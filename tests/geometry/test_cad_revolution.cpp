// Solids of full revolution with a four-sided profile as four exact quarter volume patches:
// volumes against closed forms (Pappus), conforming quarters, boundary on the CAD surfaces.
#include <gtest/gtest.h>

#include <BRepAlgoAPI_Cut.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakePolygon.hxx>
#include <BRepGProp.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakeRevol.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <GProp_GProps.hxx>
#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <gp_Ax1.hxx>

#include "cad_test_io.hpp"
#include "cad_test_parts.hpp"
#include "isospring/geometry/cad.hpp"
#include "isospring/geometry/construction.hpp"
#include "isospring/geometry/measure.hpp"

namespace isospring::geometry {
namespace {

// The four quarters join exactly: the end face of each is the start face of the next.
void expect_conforming_quarters(const std::vector<nurbs::Patch>& q) {
  ASSERT_EQ(q.size(), 4u);
  for (size_t i = 0; i < 4; ++i) {
    const nurbs::Patch a = boundary_side(q[i], 0, 1), b = boundary_side(q[(i + 1) % 4], 0, 0);
    ASSERT_EQ(a.num_points(), b.num_points());
    for (int k = 0; k < a.num_points(); ++k) {
      EXPECT_LT((a.control_point(k) - b.control_point(k)).norm(), 1e-15);
      EXPECT_NEAR(a.weight(k), b.weight(k), 1e-15);
    }
    EXPECT_GT(jacobian_range(q[i]).min, 0.0);
  }
}

TEST(CadRevolution, TubeIsFourExactQuarters) {
  // examples/cad/tube.step: radii 15 and 20 mm, 100 mm long; two cylinders and two annular caps.
  const CadModel model =
      test::step_round_trip(test::cad_test_parts()["tube.step"].shape, "tube.step");
  ASSERT_EQ(model.volume_patches.size(), 4u) << describe(model);
  EXPECT_TRUE(model.solid_notes[0].empty());
  expect_conforming_quarters(model.volume_patches);
  const double exact = M_PI * (0.02 * 0.02 - 0.015 * 0.015) * 0.1;
  EXPECT_NEAR(measure(model.volume_patches) / exact, 1.0, 1e-12);
  // Each quarter's four swept sides are on the inner cylinder, the outer one, z = 0 and z = 0.1
  // (one each), exactly.
  for (const nurbs::Patch& q : model.volume_patches) {
    std::array<int, 4> seen{};
    for (int dir = 1; dir < 3; ++dir)
      for (int side = 0; side < 2; ++side) {
        const nurbs::Patch face = boundary_side(q, dir, side);
        std::array<double, 4> off{};  // largest |r - 0.015|, |r - 0.02|, |z|, |z - 0.1|
        for (int n = 0; n <= 6; ++n)
          for (int m = 0; m <= 6; ++m) {
            const Eigen::Vector3d x = face.point(
                {face.param_min(0) + (face.param_max(0) - face.param_min(0)) * n / 6,
                 face.param_min(1) + (face.param_max(1) - face.param_min(1)) * m / 6, 0});
            const double r = std::hypot(x.x(), x.y());
            off = {std::max(off[0], std::abs(r - 0.015)), std::max(off[1], std::abs(r - 0.02)),
                   std::max(off[2], std::abs(x.z())), std::max(off[3], std::abs(x.z() - 0.1))};
          }
        const auto best = std::min_element(off.begin(), off.end());
        EXPECT_LT(*best, 1e-15);
        ++seen[static_cast<size_t>(best - off.begin())];
      }
    EXPECT_EQ(seen, (std::array<int, 4>{1, 1, 1, 1}));
  }
  EXPECT_EQ(cad_patches(model).size(), 4u);
}

TEST(CadRevolution, RevolvedTrapezoidAboutATiltedAxis) {
  // A trapezoid (inner side parallel to the axis, outer side slanted: a cone) revolved a full
  // turn about an axis through (0.01, 0.02, 0) along (1, 1, 2): a cylinder, a cone and two caps.
  const gp_Ax1 axis(gp_Pnt(0.01, 0.02, 0.0), gp_Dir(1, 1, 2));
  const gp_Dir ez = axis.Direction();
  const gp_Dir ex = gp_Ax2(axis.Location(), ez).XDirection();
  // Profile corners (radius, height) in the half-plane through ex.
  const double corners[4][2] = {{0.02, 0.0}, {0.04, 0.0}, {0.035, 0.03}, {0.02, 0.03}};
  BRepBuilderAPI_MakePolygon polygon;
  for (const auto& c : corners)
    polygon.Add(axis.Location().Translated(c[0] * gp_Vec(ex) + c[1] * gp_Vec(ez)));
  polygon.Close();
  const TopoDS_Shape part =
      BRepPrimAPI_MakeRevol(BRepBuilderAPI_MakeFace(polygon.Wire()).Face(), axis, 2 * M_PI).Shape();
  // Pappus: 2 pi x (centroid radius) x (area) of the trapezoid; for a polygon with vertices
  // (r_i, z_i): A r_c = sum (r_i + r_{i+1}) (r_i z_{i+1} - r_{i+1} z_i) / 6.
  double moment = 0.0;
  for (int i = 0; i < 4; ++i) {
    const double* a = corners[i];
    const double* b = corners[(i + 1) % 4];
    moment += (a[0] + b[0]) * (a[0] * b[1] - b[0] * a[1]) / 6;
  }
  const double exact = 2 * M_PI * std::abs(moment);
  GProp_GProps props;
  BRepGProp::VolumeProperties(part, props, 1e-9);
  ASSERT_NEAR(props.Mass() / exact, 1.0, 1e-9);
  const CadModel model = test::step_round_trip(part, "revolved_trapezoid.step");
  ASSERT_EQ(model.volume_patches.size(), 4u) << describe(model);
  expect_conforming_quarters(model.volume_patches);
  // STEP carries 12 significant digits (the tilted axis is not exact in the file).
  EXPECT_NEAR(measure(model.volume_patches) / exact, 1.0, 1e-10);
}

TEST(CadRevolution, SolidCylinderHasACollapsedAxis) {
  // Three faces (side and two discs): the profile is closed by the axis segment.
  const double r = 0.01, h = 0.03;
  const TopoDS_Shape part =
      BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0.1, 0, 0), gp_Dir(0, 1, 0)), r, h).Shape();
  const CadModel model = test::step_round_trip(part, "solid_cylinder.step");
  ASSERT_EQ(model.volume_patches.size(), 4u) << describe(model);
  expect_conforming_quarters(model.volume_patches);  // Jacobian > 0 inside, 0 on the axis
  EXPECT_NEAR(measure(model.volume_patches) / (M_PI * r * r * h), 1.0, 1e-12);
}

// Third-party files (../shared/cad): a 10 mm cube and a cylinder of radius 5 mm, height 10 mm;
// the AP203 torus.
TEST(CadRevolution, SharedCubeCylinderAndTorusAreVolumes) {
  const auto file =
      std::filesystem::path(ISOSPRING_SHARED_DIR) / "cad" / "cube_cylinder_cadquery.step";
  if (!std::filesystem::exists(file)) GTEST_SKIP() << "../shared/cad is not present";
  const CadModel model = read_cad(file);
  ASSERT_EQ(model.solids, 2);
  EXPECT_EQ(model.solid_notes, (std::vector<std::string>{"", ""})) << describe(model);
  ASSERT_EQ(model.volume_patches.size(), 5u);  // the cylinder's quarters (solid 0), the cube
  const std::vector<nurbs::Patch> cylinder(model.volume_patches.begin(),
                                           model.volume_patches.begin() + 4);
  expect_conforming_quarters(cylinder);
  // Exact: 1000 mm^3 + 250 pi mm^3 (the README's closed form; OCCT agrees to 3e-10).
  EXPECT_NEAR(measure(model.volume_patches[4]) / 1e-6, 1.0, 1e-12);
  EXPECT_NEAR(measure(cylinder) / (250 * M_PI * 1e-9), 1.0, 1e-12);
  EXPECT_EQ(cad_patches(model).size(), 5u);
  // The AP203 torus (R 200 mm, r 50 mm): exact 2 pi^2 R r^2.
  const CadModel torus = read_cad(file.parent_path() / "torus_ap203.stp");
  ASSERT_EQ(torus.volume_patches.size(), 4u) << describe(torus);
  EXPECT_NEAR(measure(torus.volume_patches) / (2 * M_PI * M_PI * 0.2 * 0.05 * 0.05), 1.0, 1e-12);
}

TEST(CadRevolution, SolidTorusIsFourQuartersWithADiskSection) {
  // One face: the closed meridian circle is cut into four arcs whose Coons patch is the
  // single-patch disk (as in the torus primitive: zero Jacobian only at its four corner lines).
  const double R = 0.0875, r = 0.0375;
  const CadModel model =
      test::step_round_trip(test::cad_test_parts()["torus.step"].shape, "torus_solid.step");
  ASSERT_EQ(model.volume_patches.size(), 4u) << describe(model);
  expect_conforming_quarters(model.volume_patches);
  EXPECT_NEAR(measure(model.volume_patches) / (2 * M_PI * M_PI * R * r * r), 1.0, 1e-12);
  for (const nurbs::Patch& q : model.volume_patches)  // the swept sides are on the torus
    for (int dir = 1; dir < 3; ++dir)
      for (int side = 0; side < 2; ++side) {
        const nurbs::Patch face = boundary_side(q, dir, side);
        for (int n = 0; n <= 6; ++n)
          for (int m = 0; m <= 6; ++m) {
            const Eigen::Vector3d x = face.point(
                {face.param_min(0) + (face.param_max(0) - face.param_min(0)) * n / 6,
                 face.param_min(1) + (face.param_max(1) - face.param_min(1)) * m / 6, 0});
            EXPECT_NEAR(std::hypot(std::hypot(x.x(), x.y()) - R, x.z()), r, 1e-15);
          }
      }
}

TEST(CadRevolution, OtherSolidsAreReported) {
  // A ball: one face whose meridian is a half circle (pole to pole), not a closed profile.
  const CadModel ball = test::step_round_trip(BRepPrimAPI_MakeSphere(0.05).Shape(), "ball.step");
  EXPECT_TRUE(ball.volume_patches.empty());
  ASSERT_EQ(ball.solid_notes.size(), 1u);
  EXPECT_NE(ball.solid_notes[0].find("meridian is not closed"), std::string::npos)
      << ball.solid_notes[0];
  EXPECT_NE(describe(ball).find("solid 0: solid of revolution, but"), std::string::npos);
  // A block with a blind hole: neither hexahedral, of revolution, a prism nor a block with
  // through-holes; the note gives every reason.
  TopoDS_Shape block = BRepPrimAPI_MakeBox(0.04, 0.04, 0.02).Shape();
  block = BRepAlgoAPI_Cut(block, BRepPrimAPI_MakeCylinder(
                                     gp_Ax2(gp_Pnt(0.02, 0.02, 0.01), gp_Dir(0, 0, 1)), 0.005, 0.01)
                                     .Shape())
              .Shape();
  const CadModel blind = test::step_round_trip(block, "blind_hole_solid.step");
  EXPECT_TRUE(blind.volume_patches.empty());
  EXPECT_NE(blind.solid_notes[0].find("not hexahedral"), std::string::npos);
  EXPECT_NE(blind.solid_notes[0].find("not a prism of a planar face"), std::string::npos);
  EXPECT_NE(blind.solid_notes[0].find("a hole ends inside the solid"), std::string::npos);
}

}  // namespace
}  // namespace isospring::geometry
