// The one list of CAD face recognisers (cad_face_recognisers.hpp), explicit for the same reason
// as the solids' (cad_solid_recognisers.cpp). The order is part of the result: a face that covers
// its whole parameter rectangle is used as it is (exact, no construction); a trimmed face of one
// wire and four edges becomes the Coons patch of its edges; any other planar face is cut into
// conforming four-sided patches. Appending keeps what existing parts become.
#include "cad_face_recognisers.hpp"

#include <BRepAdaptor_Surface.hxx>
#include <BRepGProp.hxx>
#include <GProp_GProps.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>

namespace isospring::geometry::detail {

namespace {

std::string surface_type_name(GeomAbs_SurfaceType type) {
  switch (type) {
    case GeomAbs_Plane:
      return "plane";
    case GeomAbs_Cylinder:
      return "cylinder";
    case GeomAbs_Cone:
      return "cone";
    case GeomAbs_Sphere:
      return "sphere";
    case GeomAbs_Torus:
      return "torus";
    case GeomAbs_BezierSurface:
      return "bezier";
    case GeomAbs_BSplineSurface:
      return "bspline";
    case GeomAbs_SurfaceOfRevolution:
      return "revolution";
    case GeomAbs_SurfaceOfExtrusion:
      return "extrusion";
    case GeomAbs_OffsetSurface:
      return "offset";
    default:
      return "other";
  }
}

}  // namespace

CadFace describe_face(const TopoDS_Face& face, int index) {
  CadFace report;
  report.index = index;
  report.surface_type = surface_type_name(BRepAdaptor_Surface(face).GetType());
  TopTools_IndexedMapOfShape wires, edges;
  TopExp::MapShapes(face, TopAbs_WIRE, wires);
  TopExp::MapShapes(face, TopAbs_EDGE, edges);
  report.wires = wires.Extent();
  report.edges = edges.Extent();
  GProp_GProps props;
  BRepGProp::SurfaceProperties(face, props, 1e-9);
  report.area = props.Mass();
  GProp_GProps lines;
  BRepGProp::LinearProperties(face, lines);
  report.perimeter = lines.Mass();
  return report;
}

FaceRecognition recognise_natural_face(const TopoDS_Face&, CadFace&);     // cad_natural_face.cpp
FaceRecognition recognise_coons_face(const TopoDS_Face&, CadFace&);       // cad_coons.cpp
FaceRecognition recognise_planar_cut_face(const TopoDS_Face&, CadFace&);  // cad_planar_face.cpp

const std::vector<FaceRecogniser>& face_recognisers() {
  static const std::vector<FaceRecogniser> list{
      {"natural", recognise_natural_face},
      {"coons", recognise_coons_face},
      {"planar_cut", recognise_planar_cut_face},
  };
  return list;
}

}  // namespace isospring::geometry::detail
