// Planar trimmed faces -> conforming four-sided patches of their exact edge curves.
#include "cad_planar_face.hpp"
#include "cad_face_recognisers.hpp"

#include <BRepAdaptor_Surface.hxx>
#include <BRepTools.hxx>
#include <BRepTools_WireExplorer.hxx>
#include <BRep_Tool.hxx>
#include <Standard_Failure.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Wire.hxx>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "cad_coons.hpp"
#include "isospring/geometry/construction.hpp"
#include "isospring/geometry/measure.hpp"
#include "isospring/geometry/planar_split.hpp"

namespace isospring::geometry::detail {

namespace {

bool refuse(CadFace& report, const std::string& why) {
  std::ostringstream note;
  note << "planar face (" << report.wires << " wire(s), " << report.edges
       << " edges) that cannot be cut into 4-sided patches: " << why
       << "; split it in the CAD program (or drop it with \"faces\")";
  report.note = note.str();
  return false;
}

}  // namespace

bool split_planar_face(const TopoDS_Face& face, CadFace& report,
                       std::vector<nurbs::Patch>& patches) {
  const BRepAdaptor_Surface adaptor(face);
  if (adaptor.GetType() != GeomAbs_Plane) return false;
  // Local frame of the plane, right-handed about the face's outward normal: (x, y) in the plane.
  const gp_Pln plane = adaptor.Plane();
  gp_Dir n = plane.Axis().Direction();
  if (face.Orientation() == TopAbs_REVERSED) n.Reverse();
  const gp_Dir ex = plane.XAxis().Direction();
  const gp_Dir ey = n.Crossed(ex);
  Eigen::Matrix3d frame;
  frame << ex.X(), ey.X(), n.X(), ex.Y(), ey.Y(), n.Y(), ex.Z(), ey.Z(), n.Z();
  const Eigen::Vector3d origin(plane.Location().X(), plane.Location().Y(), plane.Location().Z());
  const double tolerance = std::max(BRep_Tool::MaxTolerance(face, TopAbs_VERTEX) * 4.0, 1e-9);
  auto local = [&](const nurbs::Patch& curve) {
    nurbs::Patch c = transformed(curve, frame.transpose(), -frame.transpose() * origin);
    for (int i = 0; i < c.num_points(); ++i) {
      Eigen::Vector3d x = c.control_point(i);
      if (std::abs(x.z()) > tolerance) throw std::runtime_error("an edge leaves the face's plane");
      x.z() = 0.0;  // in the plane: the patches become 2D (signed Jacobian)
      c.set_control_point(i, x);
    }
    return c;
  };
  PlanarRegion region;
  std::vector<nurbs::Patch> local_patches;
  try {
    const TopoDS_Wire outer = BRepTools::OuterWire(face);
    if (outer.IsNull()) return refuse(report, "it has no outer wire");
    for (BRepTools_WireExplorer ex(outer, face); ex.More(); ex.Next())
      region.outline.push_back(local(edge_curve(ex.Current())));
    for (TopExp_Explorer w(face, TopAbs_WIRE); w.More(); w.Next()) {
      const TopoDS_Wire wire = TopoDS::Wire(w.Current());
      if (wire.IsSame(outer)) continue;
      std::vector<nurbs::Patch> hole;
      for (BRepTools_WireExplorer ex(wire, face); ex.More(); ex.Next())
        hole.push_back(local(edge_curve(ex.Current())));
      region.holes.push_back(hole);
    }
    local_patches = split_planar_region(region, tolerance);
  } catch (const Standard_Failure& e) {
    return refuse(report,
                  std::string("OpenCascade cannot convert an edge (") + e.GetMessageString() + ")");
  } catch (const std::exception& e) {
    return refuse(report, e.what());
  }
  // In the plane the Jacobian is signed: every patch must be right-handed.
  report.jacobian_min = std::numeric_limits<double>::infinity();
  report.jacobian_max = 0.0;
  for (size_t p = 0; p < local_patches.size(); ++p) {
    const JacobianRange range = jacobian_range(local_patches[p], 6);
    if (!(range.min > 0.0)) {
      std::ostringstream why;
      why << "patch " << p << " of the cut has a Jacobian <= 0 (min " << range.min << ")";
      return refuse(report, why.str());
    }
    report.jacobian_min = std::min(report.jacobian_min, range.min);
    report.jacobian_max = std::max(report.jacobian_max, range.max);
  }
  patches.clear();
  for (const nurbs::Patch& p : local_patches) patches.push_back(transformed(p, frame, origin));
  const double area = measure(patches);
  if (!(std::abs(area - report.area) <= 1e-9 * report.area)) {
    std::ostringstream why;
    why.precision(12);
    why << "the patches' area " << area << " m^2 differs from the face area " << report.area
        << " m^2";
    patches.clear();
    return refuse(report, why.str());
  }
  report.split = static_cast<int>(patches.size());
  report.note.clear();
  return true;
}

// Any other planar trimmed face: cut into conforming 4-sided patches.
FaceRecognition recognise_planar_cut_face(const TopoDS_Face& face, CadFace& report) {
  FaceRecognition out;
  if (report.surface_type != "plane") return out;
  out.recognised = split_planar_face(face, report, out.patches);
  out.cut = true;
  if (!out.recognised) out.patches.clear();
  return out;
}

}  // namespace isospring::geometry::detail
