// The closed-form point-in-face of planar faces bounded by lines and circles, against OpenCascade:
// the side against its exact face classifier, the distance against its projection onto each
// trimming curve.
#include <gtest/gtest.h>

#include <BRepAdaptor_Curve.hxx>
#include <BRepAdaptor_Surface.hxx>
#include <BRepAlgoAPI_Cut.hxx>
#include <BRepClass_FaceClassifier.hxx>
#include <BRepFilletAPI_MakeFillet.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepTools.hxx>
#include <BRep_Tool.hxx>
#include <Geom2dAPI_ProjectPointOnCurve.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <algorithm>
#include <cmath>
#include <limits>

#include "../../geometry/src/immersed_cad_planar_faces.hpp"

namespace isospring::geometry::detail {
namespace {

// 40 x 20 x 10 mm, two through-holes of radius 4 mm, the vertical edges rounded (r 5 mm): its
// top face is bounded by lines, quarter circles (arcs, whose ends are vertices) and full circles.
TopoDS_Face top_face() {
  TopoDS_Shape plate = BRepPrimAPI_MakeBox(0.04, 0.02, 0.01).Shape();
  for (int i = 0; i < 2; ++i)
    plate = BRepAlgoAPI_Cut(plate,
                            BRepPrimAPI_MakeCylinder(
                                gp_Ax2(gp_Pnt(0.0115 + 0.017 * i, 0.0095, -0.001), gp_Dir(0, 0, 1)),
                                0.004, 0.012)
                                .Shape())
                .Shape();
  BRepFilletAPI_MakeFillet corners(plate);
  for (TopExp_Explorer e(plate, TopAbs_EDGE); e.More(); e.Next()) {
    BRepAdaptor_Curve c(TopoDS::Edge(e.Current()));
    if (c.GetType() == GeomAbs_Line && std::abs(c.Line().Direction().Z()) > 0.99 &&
        c.Value(c.FirstParameter()).Z() < 0.011 && c.Value(c.LastParameter()).Z() > -0.001) {
      const gp_Pnt p = c.Value(c.FirstParameter());
      const bool on_corner =
          (p.X() < 1e-9 || p.X() > 0.04 - 1e-9) && (p.Y() < 1e-9 || p.Y() > 0.02 - 1e-9);
      if (on_corner) corners.Add(0.005, TopoDS::Edge(e.Current()));
    }
  }
  const TopoDS_Shape rounded = corners.Shape();
  for (TopExp_Explorer f(rounded, TopAbs_FACE); f.More(); f.Next()) {
    const TopoDS_Face face = TopoDS::Face(f.Current());
    const BRepAdaptor_Surface s(face);
    if (s.GetType() == GeomAbs_Plane &&
        std::abs(s.Value(0.5 * (s.FirstUParameter() + s.LastUParameter()),
                         0.5 * (s.FirstVParameter() + s.LastVParameter()))
                     .Z() -
                 0.01) < 1e-9)
      return face;
  }
  return {};
}

// The distance from uv to the face's trimming curves by OpenCascade's projection (and their ends).
double projected_distance(const TopoDS_Face& face, const gp_Pnt2d& uv) {
  double best = std::numeric_limits<double>::infinity();
  const TopoDS_Face forward = TopoDS::Face(face.Oriented(TopAbs_FORWARD));
  for (TopExp_Explorer e(forward, TopAbs_EDGE); e.More(); e.Next()) {
    double first = 0.0, last = 0.0;
    const Handle(Geom2d_Curve) c =
        BRep_Tool::CurveOnSurface(TopoDS::Edge(e.Current()), forward, first, last);
    best = std::min({best, uv.Distance(c->Value(first)), uv.Distance(c->Value(last))});
    Geom2dAPI_ProjectPointOnCurve projection(uv, c, first, last);
    if (projection.NbPoints() > 0) best = std::min(best, projection.LowerDistance());
  }
  return best;
}

TEST(ImmersedPlanarFaces, SideAndDistanceAgreeWithOpenCascade) {
  const TopoDS_Face face = top_face();
  ASSERT_FALSE(face.IsNull());
  const PlanarFaceBoundary boundary(face);
  ASSERT_TRUE(boundary.usable());
  double u0, u1, v0, v1;
  BRepTools::UVBounds(face, u0, u1, v0, v1);
  const TopoDS_Face forward = TopoDS::Face(face.Oriented(TopAbs_FORWARD));
  int decided = 0, undecided = 0, occt_on = 0, inside = 0, outside = 0, near = 0;
  // A grid over the UV box and a little beyond, fine enough to put points within 1e-5 of every
  // curve; its spacing is not a divisor of the holes' positions.
  const int n = 397;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const gp_Pnt2d uv(u0 - 1e-3 + (u1 - u0 + 2e-3) * i / n, v0 - 1e-3 + (v1 - v0 + 2e-3) * j / n);
      const PlanarFaceBoundary::Nearest found = boundary.nearest(uv);
      const double reference = projected_distance(face, uv);
      // Undecided only where the nearest point is a curve's end (a vertex).
      if (!found.decided) {
        EXPECT_NEAR(found.distance, reference, 1e-12);
        ++undecided;
        continue;
      }
      ++decided;
      ASSERT_NEAR(found.distance, reference, 1e-12) << uv.X() << " " << uv.Y();
      if (reference < 1e-9) continue;  // on a curve: the side is not asked for
      if (reference < 5e-5) ++near;
      const BRepClass_FaceClassifier exact(forward, uv, 1e-9);
      // OpenCascade's exact classifier says ON at one point 2.5 um outside the straight edge,
      // 30 um from where a corner's arc begins (every tolerance of the face is 1e-7): not a
      // tolerance but its probing lines near a vertex. That point is left out and counted.
      if (exact.State() == TopAbs_ON) {
        ++occt_on;
        continue;
      }
      EXPECT_EQ(found.inside, exact.State() == TopAbs_IN) << uv.X() << " " << uv.Y();
      (found.inside ? inside : outside) += 1;
    }
  std::printf(
      "decided %d of %d points (%d inside, %d outside, %d within 50 um of a curve), %d "
      "near a vertex\n",
      decided, (n + 1) * (n + 1), inside, outside, near, undecided);
  EXPECT_LT(undecided, 100);
  EXPECT_LE(occt_on, 1);
  EXPECT_GT(inside, 1000);
  EXPECT_GT(outside, 1000);
  EXPECT_GT(near, 100);
}

TEST(ImmersedPlanarFaces, OtherFacesAreLeftToOpenCascade) {
  // The cylinder of a hole: not a plane.
  const TopoDS_Shape cylinder =
      BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)), 0.004, 0.01).Shape();
  for (TopExp_Explorer f(cylinder, TopAbs_FACE); f.More(); f.Next()) {
    const TopoDS_Face face = TopoDS::Face(f.Current());
    const bool plane = BRepAdaptor_Surface(face).GetType() == GeomAbs_Plane;
    EXPECT_EQ(PlanarFaceBoundary(face).usable(), plane);
  }
}

}  // namespace
}  // namespace isospring::geometry::detail
