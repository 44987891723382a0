#pragma once
// The test parts of examples/cad, built with OpenCascade primitives (metres). The CadParts test
// writes them to a temporary folder and compares them with the committed copies; set the
// environment variable ISOSPRING_WRITE_EXAMPLE_CAD=1 to (re)write examples/cad instead.
#include <BRepAlgoAPI_Cut.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakePolygon.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakePrism.hxx>
#include <BRepPrimAPI_MakeTorus.hxx>
#include <gp_Ax2.hxx>
#include <map>
#include <string>

namespace isospring::geometry::test {

struct TestPart {
  TopoDS_Shape shape;
  double exact_volume;
};

inline std::map<std::string, TestPart> cad_test_parts() {
  std::map<std::string, TestPart> parts;
  // Hexahedral block for the demo: 100 x 20 x 20 mm.
  parts["block.step"] = {BRepPrimAPI_MakeBox(0.1, 0.02, 0.02).Shape(), 0.1 * 0.02 * 0.02};
  // Solid torus: the [S15] torus (inner radius 0.5, outer 1.25) scaled to 0.1.
  parts["torus.step"] = {BRepPrimAPI_MakeTorus(0.0875, 0.0375).Shape(),
                         2 * M_PI * M_PI * 0.0875 * 0.0375 * 0.0375};
  // Tube: radii 15 and 20 mm, length 100 mm.
  const TopoDS_Shape outer = BRepPrimAPI_MakeCylinder(0.02, 0.1).Shape();
  const TopoDS_Shape inner = BRepPrimAPI_MakeCylinder(0.015, 0.1).Shape();
  parts["tube.step"] = {BRepAlgoAPI_Cut(outer, inner).Shape(),
                        M_PI * (0.02 * 0.02 - 0.015 * 0.015) * 0.1};
  // Plate 180 x 150 x 20 mm with two holes of radius 5 mm.
  TopoDS_Shape plate = BRepPrimAPI_MakeBox(0.18, 0.15, 0.02).Shape();
  for (double x : {0.025, 0.155})
    plate = BRepAlgoAPI_Cut(plate, BRepPrimAPI_MakeCylinder(
                                       gp_Ax2(gp_Pnt(x, 0.075, 0), gp_Dir(0, 0, 1)), 0.005, 0.02)
                                       .Shape())
                .Shape();
  parts["plate_with_holes.step"] = {plate, 0.18 * 0.15 * 0.02 - 2 * M_PI * 25e-6 * 0.02};
  // L bracket: legs 50 x 10 and 10 x 60 mm, 40 mm deep, one hole of radius 4 mm in the long leg.
  BRepBuilderAPI_MakePolygon outline;
  for (auto [x, y] :
       {std::pair{0.0, 0.0}, {0.05, 0.0}, {0.05, 0.01}, {0.01, 0.01}, {0.01, 0.06}, {0.0, 0.06}})
    outline.Add(gp_Pnt(x, y, 0));
  outline.Close();
  TopoDS_Shape bracket =
      BRepPrimAPI_MakePrism(BRepBuilderAPI_MakeFace(outline.Wire()).Face(), gp_Vec(0, 0, 0.04))
          .Shape();
  bracket =
      BRepAlgoAPI_Cut(bracket, BRepPrimAPI_MakeCylinder(
                                   gp_Ax2(gp_Pnt(0, 0.04, 0.02), gp_Dir(1, 0, 0)), 0.004, 0.01)
                                   .Shape())
          .Shape();
  parts["bracket.step"] = {bracket, (0.05 * 0.01 + 0.01 * 0.05) * 0.04 - M_PI * 16e-6 * 0.01};
  return parts;
}

}  // namespace isospring::geometry::test
