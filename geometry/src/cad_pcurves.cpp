// Rebuilding pcurves that stray from their edges' 3D curves (cad_pcurves.hpp).
#include "cad_pcurves.hpp"

#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <Geom2d_Curve.hxx>
#include <Geom2d_TrimmedCurve.hxx>
#include <GeomProjLib.hxx>
#include <Geom_Curve.hxx>
#include <Geom_Surface.hxx>
#include <ShapeAnalysis_Edge.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>

namespace isospring::geometry::detail {

namespace {

// Parameters at which a pcurve is compared with its 3D curve. OpenCascade's reader uses 23, which
// a polynomial fit of a rational arc can interpolate exactly while straying between them; 400
// resolve a 25-pole cubic's oscillation (the GD&T block's, 1.9e-5 m at 400, 4e-16 m at 23).
constexpr int kSamples = 400;
// A pcurve is rebuilt only when it strays by more than this many times the edge's tolerance: the
// readers' own pcurves sit up to about the tolerance off (the tolerance is set from them).
constexpr double kStrayFactor = 2.0;

double deviation(const TopoDS_Edge& edge, const TopoDS_Face& face) {
  double deviation = 0.0;
  ShapeAnalysis_Edge().CheckSameParameter(edge, face, deviation, kSamples);
  return deviation;
}

// Projects the edge's 3D curve onto the face's surface; null when OpenCascade cannot.
Handle(Geom2d_Curve)
    projected_pcurve(const TopoDS_Edge& edge, const TopoDS_Face& face, double tolerance) {
  double first = 0.0, last = 0.0;
  const Handle(Geom_Curve) curve = BRep_Tool::Curve(edge, first, last);
  if (curve.IsNull()) return nullptr;
  // Asked for 1 % of the tolerance, so that what comes back fits well inside it.
  double reached = 0.01 * tolerance;
  Handle(Geom2d_Curve) pcurve;
  try {
    pcurve = GeomProjLib::Curve2d(curve, first, last, BRep_Tool::Surface(face), reached);
  } catch (const Standard_Failure&) {
    return nullptr;
  }
  // The projection comes trimmed to [first, last]; the edge keeps its range itself.
  const Handle(Geom2d_TrimmedCurve) trimmed = Handle(Geom2d_TrimmedCurve)::DownCast(pcurve);
  return trimmed.IsNull() ? pcurve : trimmed->BasisCurve();
}

// Replaces the edge's pcurve on the face when the projection lies within the tolerance.
bool rebuild(const TopoDS_Edge& edge, const TopoDS_Face& face) {
  const double tolerance = BRep_Tool::Tolerance(edge);
  const Handle(Geom2d_Curve) fresh = projected_pcurve(edge, face, tolerance);
  if (fresh.IsNull()) return false;
  double first = 0.0, last = 0.0, old_first = 0.0, old_last = 0.0;
  BRep_Tool::Range(edge, first, last);  // the projection's parameters are the 3D curve's
  const Handle(Geom2d_Curve) old = BRep_Tool::CurveOnSurface(edge, face, old_first, old_last);
  BRep_Builder builder;
  builder.UpdateEdge(edge, fresh, face, tolerance);
  builder.Range(edge, face, first, last);
  if (deviation(edge, face) <= tolerance) return true;
  builder.UpdateEdge(edge, old, face, tolerance);
  builder.Range(edge, face, old_first, old_last);
  return false;
}

}  // namespace

int rebuild_stray_pcurves(const TopoDS_Shape& shape) {
  TopTools_IndexedMapOfShape faces;
  TopExp::MapShapes(shape, TopAbs_FACE, faces);
  int rebuilt = 0;
  for (int f = 1; f <= faces.Extent(); ++f) {
    const TopoDS_Face& face = TopoDS::Face(faces(f));
    for (TopExp_Explorer e(face, TopAbs_EDGE); e.More(); e.Next()) {
      const TopoDS_Edge& edge = TopoDS::Edge(e.Current());
      if (BRep_Tool::Degenerated(edge) || BRep_Tool::IsClosed(edge, face)) continue;
      double first = 0.0, last = 0.0;
      if (BRep_Tool::CurveOnSurface(edge, face, first, last).IsNull()) continue;
      if (deviation(edge, face) <= kStrayFactor * BRep_Tool::Tolerance(edge)) continue;
      if (rebuild(edge, face)) ++rebuilt;
    }
  }
  return rebuilt;
}

}  // namespace isospring::geometry::detail
