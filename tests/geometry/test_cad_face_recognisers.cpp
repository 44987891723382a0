// The list of CAD face recognisers (geometry/src/cad_face_recognisers.hpp): its order, and which
// recogniser takes which kind of face, on faces built with OpenCascade: a whole rectangle
// (natural), a trapezoid trimmed from a larger plane (Coons), a square with a round hole (cut).
// Every accepted face's patches have OpenCascade's face area.
#include <gtest/gtest.h>

#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakePolygon.hxx>
#include <BRepBuilderAPI_MakeWire.hxx>
#include <Geom_Plane.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Wire.hxx>
#include <gp_Circ.hxx>
#include <gp_Pln.hxx>

#include "../../geometry/src/cad_face_recognisers.hpp"
#include "isospring/geometry/measure.hpp"

namespace isospring::geometry {
namespace {

// The name of the first recogniser that accepts the face, and its patches' total area.
std::pair<std::string, double> first_acceptor(const TopoDS_Face& face, CadFace& report) {
  for (const detail::FaceRecogniser& r : detail::face_recognisers()) {
    const detail::FaceRecognition found = r.recognise(face, report);
    if (!found.recognised) continue;
    double area = 0.0;
    for (const auto& patch : found.patches) area += measure(patch);
    return {r.name, area};
  }
  return {"", 0.0};
}

TopoDS_Face polygon_face(const std::vector<gp_Pnt>& corners, bool on_larger_plane) {
  BRepBuilderAPI_MakePolygon polygon;
  for (const gp_Pnt& p : corners) polygon.Add(p);
  polygon.Close();
  if (!on_larger_plane) return BRepBuilderAPI_MakeFace(polygon.Wire()).Face();
  return BRepBuilderAPI_MakeFace(gp_Pln(gp::Origin(), gp::DZ()), polygon.Wire()).Face();
}

TEST(CadFaceRecognisers, OrderIsNaturalThenCoonsThenCut) {
  std::vector<std::string> names;
  for (const auto& r : detail::face_recognisers()) names.push_back(r.name);
  EXPECT_EQ(names, (std::vector<std::string>{"natural", "coons", "planar_cut"}));
}

TEST(CadFaceRecognisers, AWholeRectangleIsItsOwnPatch) {
  const TopoDS_Face face = BRepBuilderAPI_MakeFace(gp_Pln(gp::Origin(), gp::DZ()), 0, 2, 0, 1);
  CadFace report = detail::describe_face(face, 0);
  const auto [name, area] = first_acceptor(face, report);
  EXPECT_EQ(name, "natural");
  EXPECT_TRUE(report.natural);
  EXPECT_NEAR(area, 2.0, 1e-12);
}

TEST(CadFaceRecognisers, ATrimmedQuadrilateralIsACoonsPatch) {
  // A trapezoid on the unbounded plane: not the plane's parameter rectangle, four edges.
  const TopoDS_Face face =
      polygon_face({gp_Pnt(0, 0, 0), gp_Pnt(3, 0, 0), gp_Pnt(2, 1, 0), gp_Pnt(1, 1, 0)}, true);
  CadFace report = detail::describe_face(face, 0);
  const auto [name, area] = first_acceptor(face, report);
  EXPECT_EQ(name, "coons") << report.note;
  EXPECT_FALSE(report.natural);
  EXPECT_TRUE(report.coons);
  EXPECT_NEAR(area, 2.0, 1e-9);
}

TEST(CadFaceRecognisers, ASquareWithAHoleIsCut) {
  BRepBuilderAPI_MakeFace maker(
      polygon_face({gp_Pnt(-2, -2, 0), gp_Pnt(2, -2, 0), gp_Pnt(2, 2, 0), gp_Pnt(-2, 2, 0)}, true));
  const TopoDS_Edge circle =
      BRepBuilderAPI_MakeEdge(gp_Circ(gp_Ax2(gp::Origin(), gp::DZ()), 1.0)).Edge();
  TopoDS_Wire hole = BRepBuilderAPI_MakeWire(circle).Wire();
  hole.Reverse();  // inner wires run clockwise
  maker.Add(hole);
  const TopoDS_Face face = maker.Face();
  CadFace report = detail::describe_face(face, 0);
  ASSERT_EQ(report.wires, 2);
  const auto [name, area] = first_acceptor(face, report);
  EXPECT_EQ(name, "planar_cut") << report.note;
  EXPECT_GT(report.split, 1);
  EXPECT_NEAR(area, 16.0 - M_PI, 1e-9);
}

}  // namespace
}  // namespace isospring::geometry
