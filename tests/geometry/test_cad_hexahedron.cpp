// Solids of hexahedral topology with curved edges and faces as one transfinite NURBS volume:
// volumes against closed forms and BRepGProp, faces on the CAD surfaces, positive Jacobians;
// prisms of faces that are not the blend of their edges as exact extrusions.
#include <gtest/gtest.h>

#include <BRepAlgoAPI_Common.hxx>
#include <BRepAlgoAPI_Cut.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepGProp.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakePrism.hxx>
#include <GProp_GProps.hxx>
#include <Geom_BSplineSurface.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <cmath>
#include <random>

#include "cad_test_io.hpp"
#include "isospring/geometry/cad.hpp"
#include "isospring/geometry/construction.hpp"
#include "isospring/geometry/measure.hpp"

namespace isospring::geometry {
namespace {

double occt_volume(const TopoDS_Shape& shape) {
  GProp_GProps props;
  BRepGProp::VolumeProperties(shape, props, 1e-9);
  return props.Mass();
}

TEST(CadHexahedron, TubeSectorIsOneTransfiniteVolume) {
  // Quarter of a tube, radii 15 and 20 mm, 50 mm long: two cylindrical faces, two planar annular
  // sectors (trimmed planes with two arcs and two lines) and two rectangles.
  const double R = 0.02, r = 0.015, h = 0.05;
  const TopoDS_Shape part = BRepAlgoAPI_Cut(BRepPrimAPI_MakeCylinder(R, h, M_PI / 2).Shape(),
                                            BRepPrimAPI_MakeCylinder(r, h).Shape())
                                .Shape();
  const double exact = M_PI / 4 * (R * R - r * r) * h;
  ASSERT_NEAR(occt_volume(part) / exact, 1.0, 1e-9);
  const CadModel model = test::step_round_trip(part, "tube_sector.step");
  ASSERT_EQ(model.volume_patches.size(), 1u) << describe(model);
  const nurbs::Patch& volume = model.volume_patches[0];
  EXPECT_TRUE(volume.is_rational());
  // Exact boundary and a positive Jacobian: the volume integral is the solid's volume (Gauss on
  // the rational quarter arcs reaches round-off, see measure.hpp).
  EXPECT_NEAR(measure(volume) / exact, 1.0, 1e-12);
  EXPECT_NEAR(measure(volume) / occt_volume(part), 1.0, 1e-9);  // BRepGProp at eps 1e-9
  EXPECT_GT(jacobian_range(volume).min, 0.0);
  // Every sample (boundary and inside) is in the tube sector; every boundary sample is on one of
  // its six surfaces: r = 15 mm, r = 20 mm, z = 0, z = h, x = 0 or y = 0.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0, 1);
  for (int n = 0; n < 200; ++n) {
    nurbs::Param u{unit(rng), unit(rng), unit(rng)};
    const bool boundary = n % 2 == 0;
    if (boundary) u[static_cast<size_t>(n / 2 % 3)] = (n / 6) % 2;
    const Eigen::Vector3d x = volume.point(u);
    const double radius = std::hypot(x.x(), x.y());
    EXPECT_GE(radius, r - 1e-15);
    EXPECT_LE(radius, R + 1e-15);
    EXPECT_GE(std::min({x.x(), x.y(), x.z(), h - x.z()}), -1e-15);
    if (boundary) {
      const double off = std::min({std::abs(radius - r), std::abs(radius - R), std::abs(x.z()),
                                   std::abs(x.z() - h), std::abs(x.x()), std::abs(x.y())});
      EXPECT_LT(off, 1e-15) << x.transpose();
    }
  }
  EXPECT_EQ(cad_patches(model).size(), 1u);  // an analysis gets the volume
}

TEST(CadHexahedron, ThreeQuarterTubeIsOneRightHandedVolume) {
  // 270 degrees: the straight corner-to-corner vectors no longer show the block's handedness.
  const double R = 0.02, r = 0.015, h = 0.05;
  const TopoDS_Shape part = BRepAlgoAPI_Cut(BRepPrimAPI_MakeCylinder(R, h, 1.5 * M_PI).Shape(),
                                            BRepPrimAPI_MakeCylinder(r, h).Shape())
                                .Shape();
  const CadModel model = test::step_round_trip(part, "tube_three_quarters.step");
  ASSERT_EQ(model.volume_patches.size(), 1u) << describe(model);
  EXPECT_GT(jacobian_range(model.volume_patches[0]).min, 0.0);
  EXPECT_NEAR(measure(model.volume_patches[0]) / (0.75 * M_PI * (R * R - r * r) * h), 1.0, 1e-12);
}

TEST(CadHexahedron, BoxWithACylindricalTop) {
  // Box 100 x 50 x 50 mm whose top is replaced by a cylinder of radius 0.24 m about the line
  // y = 0.025, z = -0.2 (a shallow vault; the top face is cylindrical, the x = const sides are
  // planes with an arc on top).
  const double Rc = 0.24, a = 0.025;
  const TopoDS_Shape cylinder =
      BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(-0.01, a, -0.2), gp_Dir(1, 0, 0), gp_Dir(0, 0, -1)),
                               Rc, 0.12)
          .Shape();  // seam underneath, away from the box
  const TopoDS_Shape part =
      BRepAlgoAPI_Common(BRepPrimAPI_MakeBox(0.1, 0.05, 0.05).Shape(), cylinder).Shape();
  // Cross-section: the circular segment above z = -0.2 over |y - a| <= a, minus 0.2 * 2a.
  const double section = a * std::sqrt(Rc * Rc - a * a) + Rc * Rc * std::asin(a / Rc) - 0.2 * 2 * a;
  const double exact = 0.1 * section;
  ASSERT_NEAR(occt_volume(part) / exact, 1.0, 1e-9);
  const CadModel model = test::step_round_trip(part, "vault.step");
  ASSERT_EQ(model.volume_patches.size(), 1u) << describe(model);
  const nurbs::Patch& volume = model.volume_patches[0];
  EXPECT_NEAR(measure(volume) / exact, 1.0, 1e-12);
  EXPECT_GT(jacobian_range(volume).min, 0.0);
  // Numbered like the box: u along x, v along y, w up; the top (w = 1) is on the cylinder.
  EXPECT_LT(volume.point({0, 0, 0}).norm(), 1e-15);
  EXPECT_LT((volume.point({1, 0, 0}) - Eigen::Vector3d(0.1, 0, 0)).norm(), 1e-15);
  EXPECT_LT((volume.point({0, 1, 0}) - Eigen::Vector3d(0, 0.05, 0)).norm(), 1e-15);
  for (int n = 0; n <= 10; ++n)
    for (int m = 0; m <= 10; ++m) {
      const Eigen::Vector3d x = volume.point({n / 10.0, m / 10.0, 1.0});
      EXPECT_NEAR(std::hypot(x.y() - a, x.z() + 0.2), Rc, 1e-15);
    }
}

TEST(CadHexahedron, PrismOfABumpedSplineFaceIsItsExtrusion) {
  // Base: a bicubic Bezier face over the 100 mm square with two raised interior poles (not the
  // blend of its four straight edges), extruded 50 mm along z by BRepPrimAPI_MakePrism.
  TColgp_Array2OfPnt poles(1, 4, 1, 4);
  for (int i = 1; i <= 4; ++i)
    for (int j = 1; j <= 4; ++j)
      poles.SetValue(i, j,
                     gp_Pnt(0.1 * (i - 1) / 3.0, 0.1 * (j - 1) / 3.0,
                            (i == 2 && j == 2) || (i == 3 && j == 2) ? 0.01 : 0.0));
  TColStd_Array1OfReal knots(1, 2);
  knots.SetValue(1, 0.0);
  knots.SetValue(2, 1.0);
  TColStd_Array1OfInteger mults(1, 2);
  mults.SetValue(1, 4);
  mults.SetValue(2, 4);
  const Handle(Geom_BSplineSurface) surface =
      new Geom_BSplineSurface(poles, knots, knots, mults, mults, 3, 3);
  const TopoDS_Face base = BRepBuilderAPI_MakeFace(surface, 1e-9).Face();
  const TopoDS_Shape part = BRepPrimAPI_MakePrism(base, gp_Vec(0, 0, 0.05)).Shape();
  // Poles at the Greville abscissae: x = 0.1 u, y = 0.1 v, so the base projects onto the square
  // and the prism's volume is 0.01 m^2 x 0.05 m whatever the bump.
  const double exact = 0.01 * 0.05;
  ASSERT_NEAR(occt_volume(part) / exact, 1.0, 1e-9);
  const CadModel model = test::step_round_trip(part, "bumped_prism.step");
  ASSERT_EQ(model.volume_patches.size(), 1u) << describe(model);
  EXPECT_TRUE(model.solid_notes[0].empty());
  const nurbs::Patch& volume = model.volume_patches[0];
  EXPECT_NEAR(measure(volume) / exact, 1.0, 1e-12);
  EXPECT_GT(jacobian_range(volume).min, 0.0);
  // One direction is the extrusion: degree 1 with the 50 mm offset along z.
  int extrusion = -1;
  for (int d = 0; d < 3; ++d)
    if (volume.degree(d) == 1) extrusion = d;
  ASSERT_GE(extrusion, 0);
  nurbs::Param lo{0.3, 0.6, 0.2}, hi = lo;
  lo[static_cast<size_t>(extrusion)] = 0.0;
  hi[static_cast<size_t>(extrusion)] = 1.0;
  EXPECT_LT(((volume.point(hi) - volume.point(lo)).cwiseAbs() - Eigen::Vector3d(0, 0, 0.05)).norm(),
            1e-15);
  // The base side is the bumped surface: compare with OCCT's evaluation at the same (x, y).
  const Eigen::Vector3d x = volume.point(volume.point(lo).z() < volume.point(hi).z() ? lo : hi);
  const gp_Pnt on = surface->Value(x.x() / 0.1, x.y() / 0.1);
  EXPECT_LT((x - Eigen::Vector3d(on.X(), on.Y(), on.Z())).norm(), 1e-15);
  EXPECT_GT(x.z(), 1e-3);  // really on the bump
}

}  // namespace
}  // namespace isospring::geometry
