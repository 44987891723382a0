// The faces of a CAD solid for selection (see cad_face_selection.hpp): type, area, centroid,
// box, plane normal or cylinder axis, STEP name, and the sample points the selectors test.
#include <BRepAdaptor_Curve.hxx>
#include <BRepAdaptor_Surface.hxx>
#include <BRepGProp.hxx>
#include <BRepTools.hxx>
#include <BRepTopAdaptor_FClass2d.hxx>
#include <BRep_Tool.hxx>
#include <GProp_GProps.hxx>
#include <Interface_Static.hxx>
#include <STEPControl_Controller.hxx>
#include <STEPControl_Reader.hxx>
#include <Standard_Failure.hxx>
#include <StepRepr_RepresentationItem.hxx>
#include <TCollection_HAsciiString.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <Transfer_TransientProcess.hxx>
#include <XSControl_TransferReader.hxx>
#include <XSControl_WorkSession.hxx>
#include <algorithm>
#include <cctype>
#include <map>

#include "cad_face_recognisers.hpp"
#include "cad_solid_shape.hpp"
#include "isospring/geometry/cad_face_selection.hpp"
#include "isospring/nurbs/error.hpp"
#include "occt_box.hpp"
#include "occt_silence.hpp"

namespace isospring::geometry {
namespace {

constexpr int kEdgeSamples = 16;  // intervals per edge
constexpr int kGridSamples = 8;   // interior grid per parameter direction

Eigen::Vector3d vec(const gp_XYZ& p) {
  return {p.X(), p.Y(), p.Z()};
}

bool is_step(const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".step" || ext == ".stp";
}

// The names of the file's faces, by file index (as read_cad_shape numbers them: the faces of the
// transferred shape in TopExp::MapShapes order). Empty when the file is not STEP or cannot be
// read again (the solid was read from it already, so that would be a race with the file system;
// selection by name then finds nothing and says so).
std::vector<std::string> step_face_names(const std::filesystem::path& file) {
  if (!is_step(file) || !std::filesystem::is_regular_file(file)) return {};
  STEPControl_Controller::Init();
  Interface_Static::SetCVal("xstep.cascade.unit", "M");
  const detail::SilenceOpenCascade silence;
  STEPControl_Reader reader;
  if (reader.ReadFile(file.string().c_str()) != IFSelect_RetDone) return {};
  reader.TransferRoots();
  const TopoDS_Shape shape = reader.OneShape();
  TopTools_IndexedMapOfShape faces;
  TopExp::MapShapes(shape, TopAbs_FACE, faces);
  const Handle(XSControl_TransferReader) transfer = reader.WS()->TransferReader();
  std::vector<std::string> names(static_cast<size_t>(faces.Extent()));
  for (int f = 1; f <= faces.Extent(); ++f) {
    const Handle(StepRepr_RepresentationItem) item =
        Handle(StepRepr_RepresentationItem)::DownCast(transfer->EntityFromShapeResult(faces(f), 1));
    if (!item.IsNull() && !item->Name().IsNull())
      names[static_cast<size_t>(f - 1)] = item->Name()->ToCString();
  }
  return names;
}

// Points of the face's edges and of an interior parameter grid that lie on the face.
std::vector<Eigen::Vector3d> face_samples(const TopoDS_Face& face) {
  std::vector<Eigen::Vector3d> samples;
  TopTools_IndexedMapOfShape edges;
  TopExp::MapShapes(face, TopAbs_EDGE, edges);
  for (int e = 1; e <= edges.Extent(); ++e) {
    const TopoDS_Edge edge = TopoDS::Edge(edges(e));
    if (BRep_Tool::Degenerated(edge)) continue;
    const BRepAdaptor_Curve curve(edge);
    const double t0 = curve.FirstParameter(), t1 = curve.LastParameter();
    for (int k = 0; k <= kEdgeSamples; ++k)
      samples.push_back(vec(curve.Value(t0 + (t1 - t0) * k / kEdgeSamples).XYZ()));
  }
  double u0 = 0, u1 = 0, v0 = 0, v1 = 0;
  BRepTools::UVBounds(face, u0, u1, v0, v1);
  const BRepAdaptor_Surface surface(face);
  BRepTopAdaptor_FClass2d classifier(face, 1e-9);
  for (int i = 0; i < kGridSamples; ++i)
    for (int j = 0; j < kGridSamples; ++j) {
      const double u = u0 + (u1 - u0) * (i + 0.5) / kGridSamples;
      const double v = v0 + (v1 - v0) * (j + 0.5) / kGridSamples;
      if (classifier.Perform(gp_Pnt2d(u, v)) == TopAbs_IN)
        samples.push_back(vec(surface.Value(u, v).XYZ()));
    }
  return samples;
}

SolidFace describe_solid_face(const TopoDS_Face& face, int index) {
  SolidFace f;
  f.index = index;
  const CadFace report = detail::describe_face(face, index);
  f.surface_type = report.surface_type;
  GProp_GProps props;
  BRepGProp::SurfaceProperties(face, props, 1e-9);
  f.area = props.Mass();
  f.centroid = vec(props.CentreOfMass().XYZ());
  const detail::Corners box = detail::tight_box(face);
  f.box_min = box.lo;
  f.box_max = box.hi;
  const BRepAdaptor_Surface surface(face);
  if (surface.GetType() == GeomAbs_Plane) {
    const gp_Pln plane = surface.Plane();
    // The plane's normal follows its axis; the face's orientation in the solid may reverse it,
    // and a plane's axis may be left-handed (then the normal is the cross product of the axes).
    gp_Dir n =
        plane.Position().Direct() ? plane.Axis().Direction() : plane.Axis().Direction().Reversed();
    if (face.Orientation() == TopAbs_REVERSED) n.Reverse();
    f.normal = vec(n.XYZ());
  } else if (surface.GetType() == GeomAbs_Cylinder) {
    const gp_Cylinder c = surface.Cylinder();
    f.axis_point = vec(c.Location().XYZ());
    f.axis = vec(c.Axis().Direction().XYZ());
    f.radius = c.Radius();
  }
  f.samples = face_samples(face);
  return f;
}

}  // namespace

std::vector<SolidFace> solid_faces(const CadSolid& solid) {
  const CadSolid::Shape& shape = solid.shape();
  const std::vector<std::string> names = step_face_names(solid.name());
  std::vector<SolidFace> faces;
  try {
    for (size_t k = 0; k < shape.faces.size(); ++k) {
      SolidFace f = describe_solid_face(shape.faces[k], shape.face_index[k]);
      if (f.index >= 0 && static_cast<size_t>(f.index) < names.size())
        f.name = names[static_cast<size_t>(f.index)];
      faces.push_back(std::move(f));
    }
  } catch (const Standard_Failure& e) {
    throw nurbs::InputError(solid.name() + ": OpenCascade failed describing its faces (" +
                            e.GetMessageString() + "); check the part in the CAD program");
  }
  return faces;
}

}  // namespace isospring::geometry
