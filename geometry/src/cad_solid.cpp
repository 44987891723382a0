// One solid of a CAD file, checked for immersion (immersed_cad.hpp, cad_solid_shape.hpp).
#include <BRepAdaptor_Surface.hxx>
#include <BRepBuilderAPI_Sewing.hxx>
#include <BRepCheck_Analyzer.hxx>
#include <BRepGProp.hxx>
#include <BRepLib.hxx>
#include <BRep_Tool.hxx>
#include <GProp_GProps.hxx>
#include <ShapeFix_Solid.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Shell.hxx>

#include "cad_reader.hpp"
#include "cad_solid_shape.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::geometry {

using nurbs::InputError;

CadSolid::CadSolid(std::shared_ptr<const Shape> shape, std::string name)
    : shape_(std::move(shape)), name_(std::move(name)) {}

int CadSolid::face_count() const {
  return shape_->file_faces;
}

namespace {

constexpr double kSewingTolerance = 1e-6;  // m; CAD exporters' usual gap tolerance

// Edges used by one face only (a seam is used twice by its face, a degenerated edge at a pole
// once, and neither is a gap).
int free_edges(const TopoDS_Shape& shape) {
  TopTools_IndexedDataMapOfShapeListOfShape edge_faces;
  TopExp::MapShapesAndAncestors(shape, TopAbs_EDGE, TopAbs_FACE, edge_faces);
  int count = 0;
  for (int e = 1; e <= edge_faces.Extent(); ++e)
    if (edge_faces(e).Extent() == 1 && !BRep_Tool::Degenerated(TopoDS::Edge(edge_faces.FindKey(e))))
      ++count;
  return count;
}

// Closed, valid and of positive volume, or an InputError naming the fix. A solid whose shell is
// inside out (negative volume) is turned around: that is an orientation flag, not a repair.
TopoDS_Solid checked(TopoDS_Solid solid, const std::string& name) {
  if (const int open = free_edges(solid); open > 0)
    throw InputError(name + ": the solid is an open shell (" + std::to_string(open) +
                     " edges belong to one face only): close it in the CAD program (every edge "
                     "shared by two faces) and export it again");
  BRepCheck_Analyzer analyzer(solid);
  if (!analyzer.IsValid())
    throw InputError(name +
                     ": the solid is not valid (OpenCascade's BRepCheck_Analyzer finds faults "
                     "in its faces, edges or shells): repair it in the CAD program (check "
                     "geometry / heal) and export it again");
  GProp_GProps props;
  BRepGProp::VolumeProperties(solid, props);
  if (props.Mass() < 0.0) solid.Reverse();
  if (!(std::abs(props.Mass()) > 0.0))
    throw InputError(name + ": the solid encloses no volume; export a closed solid part");
  return solid;
}

// Planar faces read from STEP often carry no pcurves (the curves of their edges in the plane's
// parameters): OpenCascade then projects the edge onto the plane at every query
// (BRep_Tool::CurveOnPlane), and its exact point-in-face classifier asks for every edge of the
// face at every call, which was a sixth of the immersion's time on a plate with 32 holes. Each
// projection is stored once; BRepLib stores exactly the curve the query computes, so every
// later answer is the same.
void store_plane_pcurves(const std::vector<TopoDS_Face>& faces) {
  for (const TopoDS_Face& face : faces) {
    if (BRepAdaptor_Surface(face, false).GetType() != GeomAbs_Plane) continue;
    for (TopExp_Explorer e(face, TopAbs_EDGE); e.More(); e.Next())
      BRepLib::BuildPCurveForEdgeOnPlane(TopoDS::Edge(e.Current()), face);
  }
}

std::shared_ptr<CadSolid::Shape> shape_of(const TopoDS_Solid& solid,
                                          const TopTools_IndexedMapOfShape& file_faces,
                                          const std::vector<int>& sewn_origin) {
  auto shape = std::make_shared<CadSolid::Shape>();
  shape->solid = solid;
  shape->file_faces = file_faces.Extent();
  TopTools_IndexedMapOfShape faces;
  TopExp::MapShapes(solid, TopAbs_FACE, faces);
  for (int f = 1; f <= faces.Extent(); ++f) {
    shape->faces.push_back(TopoDS::Face(faces(f)));
    const int index = file_faces.FindIndex(faces(f));
    shape->face_index.push_back(index > 0 ? index - 1
                                          : (sewn_origin.empty() ? f - 1 : sewn_origin[f - 1]));
  }
  store_plane_pcurves(shape->faces);
  return shape;
}

// Faces without a solid (IGES surfaces): sewn into one closed shell and made a solid. Returns
// the solid and, per face of it, the file index of the face it was sewn from.
TopoDS_Solid sewn_solid(const TopTools_IndexedMapOfShape& file_faces, const std::string& name,
                        std::vector<int>& origin) {
  BRepBuilderAPI_Sewing sewing(kSewingTolerance);
  for (int f = 1; f <= file_faces.Extent(); ++f) sewing.Add(file_faces(f));
  sewing.Perform();
  const TopoDS_Shape sewn = sewing.SewedShape();
  TopTools_IndexedMapOfShape shells;
  TopExp::MapShapes(sewn, TopAbs_SHELL, shells);
  const int open = free_edges(sewn);
  if (shells.Extent() != 1 || open > 0)
    throw InputError(name + ": the faces do not close a volume (after sewing at 1e-6 m: " +
                     std::to_string(shells.Extent()) + " shell(s), " + std::to_string(open) +
                     " free edges): it is an open shell; close it in the CAD program and export "
                     "a solid");
  const TopoDS_Solid solid = ShapeFix_Solid().SolidFromShell(TopoDS::Shell(shells(1)));
  TopTools_IndexedMapOfShape faces;
  TopExp::MapShapes(solid, TopAbs_FACE, faces);
  origin.assign(static_cast<size_t>(faces.Extent()), -1);
  for (int f = 1; f <= file_faces.Extent(); ++f) {
    const TopoDS_Shape result =
        sewing.IsModified(file_faces(f)) ? sewing.Modified(file_faces(f)) : file_faces(f);
    const int index = faces.FindIndex(result);
    if (index > 0) origin[static_cast<size_t>(index - 1)] = f - 1;
  }
  return solid;
}

CadSolid read_unguarded(const std::filesystem::path& file, int solid) {
  const std::string name = file.string();
  std::string unit;
  const TopoDS_Shape shape = detail::read_cad_shape(file, unit);
  TopTools_IndexedMapOfShape file_faces, solids;
  TopExp::MapShapes(shape, TopAbs_FACE, file_faces);
  TopExp::MapShapes(shape, TopAbs_SOLID, solids);
  if (file_faces.Extent() == 0)
    throw InputError(name + ": the file holds no faces; a part for immersion needs a solid");
  if (solids.Extent() == 0) {
    if (solid > 0)
      throw InputError(name + ": solid " + std::to_string(solid) +
                       " does not exist: the file holds faces only (sewn into one solid, 0)");
    std::vector<int> origin;
    const TopoDS_Solid sewn = checked(sewn_solid(file_faces, name, origin), name);
    return CadSolid(shape_of(sewn, file_faces, origin), name);
  }
  if (solid < 0 && solids.Extent() > 1)
    throw InputError(name + ": the file holds " + std::to_string(solids.Extent()) +
                     " solids; an immersed domain is one solid: choose one (solid 0.." +
                     std::to_string(solids.Extent() - 1) +
                     ", as `isospring info` lists them) or save each body in its own file");
  if (solid >= solids.Extent())
    throw InputError(name + ": solid " + std::to_string(solid) +
                     " does not exist; the file holds " + std::to_string(solids.Extent()) +
                     " (0-based, see `isospring info`)");
  const TopoDS_Solid chosen = checked(TopoDS::Solid(solids(std::max(solid, 0) + 1)), name);
  return CadSolid(shape_of(chosen, file_faces, {}), name);
}

}  // namespace

CadSolid read_cad_solid(const std::filesystem::path& file, int solid) {
  try {
    return read_unguarded(file, solid);
  } catch (const Standard_Failure& e) {
    throw InputError(file.string() + ": OpenCascade failed on the solid (" + e.GetMessageString() +
                     "); check it in the CAD program and export it again");
  }
}

CadSolid detail::make_cad_solid(const TopoDS_Shape& shape, const std::string& name) {
  TopTools_IndexedMapOfShape solids, faces;
  TopExp::MapShapes(shape, TopAbs_SOLID, solids);
  TopExp::MapShapes(shape, TopAbs_FACE, faces);
  if (solids.Extent() != 1)
    throw InputError(name + ": the shape holds " + std::to_string(solids.Extent()) +
                     " solids; give exactly one");
  return CadSolid(shape_of(checked(TopoDS::Solid(solids(1)), name), faces, {}), name);
}

SolidMeasures measure_solid(const CadSolid& solid) {
  GProp_GProps volume, area;
  BRepGProp::VolumeProperties(solid.shape().solid, volume, 1e-10);
  BRepGProp::SurfaceProperties(solid.shape().solid, area, 1e-10);
  const gp_Pnt c = volume.CentreOfMass();
  return {volume.Mass(), area.Mass(), Eigen::Vector3d(c.X(), c.Y(), c.Z())};
}

SolidMeasures measure_quadrature(const ImmersedDomain& domain) {
  SolidMeasures m;
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  for (const ImmersedCell& cell : domain.cells)
    for (size_t q = 0; q < cell.points.size(); ++q) {
      m.volume += cell.weights[q];
      moment += cell.weights[q] * cell.points[q];
    }
  for (const BoundaryPoint& b : domain.boundary) m.area += b.weight;
  if (m.volume > 0.0) m.centroid = moment / m.volume;
  return m;
}

}  // namespace isospring::geometry
