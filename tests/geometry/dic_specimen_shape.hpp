#pragma once
// The DIC specimen of examples/dic_plate as a CAD part, built with OpenCascade from the
// published dimensions (Anton et al. 2024, "simplified dog-bone"; mm): the 80 x 20 test section
// with a hole of radius 4 at (40, 10), 5 of straight shoulder to its left, then circular fillets
// of radius 25 widening it to 30 at x = -20. Two planar faces in z = 0, as a CAD user splits a
// part where a fillet begins: the straight part with the hole ([-5, 80] x [0, 20]) and the fillet
// region ([-20, -5], between the arcs). examples/dic_plate/specimen.step is this shape
// (`DicSpecimenStep.ShippedFileIsTheDrawing`).
#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakePolygon.hxx>
#include <BRepBuilderAPI_MakeWire.hxx>
#include <BRepBuilderAPI_Sewing.hxx>
#include <GC_MakeArcOfCircle.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>
#include <TopoDS_Wire.hxx>
#include <cmath>
#include <gp_Circ.hxx>

namespace isospring::geometry::test {

inline TopoDS_Shape dic_specimen_shape() {
  const double mm = 1e-3;
  BRepBuilderAPI_MakePolygon outline(gp_Pnt(-5 * mm, 0, 0), gp_Pnt(80 * mm, 0, 0),
                                     gp_Pnt(80 * mm, 20 * mm, 0), gp_Pnt(-5 * mm, 20 * mm, 0),
                                     true);
  BRepBuilderAPI_MakeFace section(outline.Wire(), true);
  section.Add(TopoDS::Wire(
      BRepBuilderAPI_MakeWire(BRepBuilderAPI_MakeEdge(gp_Circ(
                                  gp_Ax2(gp_Pnt(40 * mm, 10 * mm, 0), gp_Dir(0, 0, 1)), 4 * mm)))
          .Wire()
          .Reversed()));
  // Fillets: circles of radius 25 centred 25 above the top side and below the bottom side at
  // x = -5 (tangent there), reaching y = 25 and y = -5 at x = -20.
  const gp_Pnt top_right(-5 * mm, 20 * mm, 0), top_left(-20 * mm, 25 * mm, 0);
  const gp_Pnt bottom_left(-20 * mm, -5 * mm, 0), bottom_right(-5 * mm, 0, 0);
  // Each arc through its middle point (angles about the centres: from -90 to -90 - theta and
  // from 90 + theta to 90 degrees, sin theta = 15 / 25), so its sense is unambiguous.
  const double theta = std::asin(15.0 / 25.0);
  const gp_Pnt top_middle((-5 - 25 * std::sin(theta / 2)) * mm,
                          (45 - 25 * std::cos(theta / 2)) * mm, 0);
  const gp_Pnt bottom_middle((-5 - 25 * std::sin(theta / 2)) * mm,
                             (-25 + 25 * std::cos(theta / 2)) * mm, 0);
  BRepBuilderAPI_MakeWire fillet_wire;
  fillet_wire.Add(BRepBuilderAPI_MakeEdge(bottom_right, top_right).Edge());
  fillet_wire.Add(
      BRepBuilderAPI_MakeEdge(GC_MakeArcOfCircle(top_right, top_middle, top_left).Value()).Edge());
  fillet_wire.Add(BRepBuilderAPI_MakeEdge(top_left, bottom_left).Edge());
  fillet_wire.Add(
      BRepBuilderAPI_MakeEdge(GC_MakeArcOfCircle(bottom_left, bottom_middle, bottom_right).Value())
          .Edge());
  const TopoDS_Face fillet = BRepBuilderAPI_MakeFace(fillet_wire.Wire(), true).Face();
  BRepBuilderAPI_Sewing sewing(1e-9);
  sewing.Add(section.Face());
  sewing.Add(fillet);
  sewing.Perform();
  return sewing.SewedShape();
}

}  // namespace isospring::geometry::test
