// Four-sided trimmed faces -> exact NURBS Coons patches of their (B-spline converted) edges.
#include "cad_coons.hpp"
#include "cad_face_recognisers.hpp"

#include <BRepTools.hxx>
#include <BRepTools_WireExplorer.hxx>
#include <BRep_Tool.hxx>
#include <Eigen/Geometry>
#include <GeomAPI_ProjectPointOnCurve.hxx>
#include <GeomAPI_ProjectPointOnSurf.hxx>
#include <GeomConvert.hxx>
#include <GeomLProp_SLProps.hxx>
#include <Geom_Surface.hxx>
#include <Geom_TrimmedCurve.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Vertex.hxx>
#include <TopoDS_Wire.hxx>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "isospring/geometry/construction.hpp"
#include "isospring/geometry/coons.hpp"
#include "isospring/geometry/measure.hpp"
#include "occt_conversion.hpp"

namespace isospring::geometry::detail {

nurbs::Patch curve_patch(const Handle(Geom_Curve) & curve, double first, double last) {
  // On a periodic curve the trimmed curve may shift the range by a period: use its own bounds.
  const Handle(Geom_TrimmedCurve) trimmed = new Geom_TrimmedCurve(curve, first, last);
  first = trimmed->FirstParameter();
  last = trimmed->LastParameter();
  Handle(Geom_BSplineCurve) bspline = GeomConvert::CurveToBSplineCurve(trimmed);
  bspline = Handle(Geom_BSplineCurve)::DownCast(bspline->Copy());
  if (bspline->IsPeriodic()) bspline->SetNotPeriodic();
  // Clamp at the ends (the conversion keeps the curve's own parameter) and cut there.
  const double a = std::max(first, bspline->FirstParameter()),
               b = std::min(last, bspline->LastParameter());
  bspline->InsertKnot(a, bspline->Degree(), 1e-12, false);
  bspline->InsertKnot(b, bspline->Degree(), 1e-12, false);
  bspline->Segment(a, b);
  nurbs::Patch patch = patch_from_occt(bspline);
  // Exact conversion (conics keep their geometry, not their parameter): the ends match the
  // curve's ends and samples lie on the original curve.
  const auto [lo, hi] = patch.control_bounds();
  const double tolerance = 1e-9 * (hi - lo).norm() + 1e-15;
  auto gap = [](const Eigen::Vector3d& x, const gp_Pnt& p) {
    return (x - Eigen::Vector3d(p.X(), p.Y(), p.Z())).norm();
  };
  if (gap(patch.point({patch.param_min(0), 0, 0}), curve->Value(first)) > tolerance ||
      gap(patch.point({patch.param_max(0), 0, 0}), curve->Value(last)) > tolerance)
    throw std::runtime_error("the B-spline conversion of a curve does not keep its ends");
  for (int n = 1; n < 8; ++n) {
    const Eigen::Vector3d x = patch.point(
        {patch.param_min(0) + (patch.param_max(0) - patch.param_min(0)) * n / 8.0, 0, 0});
    GeomAPI_ProjectPointOnCurve projection(gp_Pnt(x.x(), x.y(), x.z()), curve);
    if (projection.NbPoints() == 0 || projection.LowerDistance() > tolerance)
      throw std::runtime_error("the B-spline conversion of a curve leaves the curve");
  }
  return patch;
}

nurbs::Patch edge_curve(const TopoDS_Edge& edge) {
  if (BRep_Tool::Degenerated(edge)) {  // collapsed side (e.g. at a pole): a constant curve
    const gp_Pnt p = BRep_Tool::Pnt(TopExp::FirstVertex(edge));
    const Eigen::Vector3d x(p.X(), p.Y(), p.Z());
    return nurbs::Patch({nurbs::KnotVector(1, {0, 0, 1, 1})}, {x, x});
  }
  TopLoc_Location location;
  double first = 0.0, last = 0.0;
  const Handle(Geom_Curve) curve = BRep_Tool::Curve(edge, location, first, last);
  if (curve.IsNull()) throw std::runtime_error("an edge has no 3D curve");
  nurbs::Patch patch =
      curve_patch(location.IsIdentity()
                      ? curve
                      : Handle(Geom_Curve)::DownCast(curve->Transformed(location.Transformation())),
                  first, last);
  if (edge.Orientation() == TopAbs_REVERSED) patch = reverse_direction(patch, 0);
  return patch;
}

double surface_deviation(const nurbs::Patch& patch, const TopoDS_Face& face) {
  const Handle(Geom_Surface) surface = BRep_Tool::Surface(face);
  double deviation = 0.0;
  for (int a = 1; a < 9; ++a)
    for (int b = 1; b < 9; ++b) {
      const Eigen::Vector3d x = patch.point(
          {patch.param_min(0) + (patch.param_max(0) - patch.param_min(0)) * a / 9.0,
           patch.param_min(1) + (patch.param_max(1) - patch.param_min(1)) * b / 9.0, 0});
      GeomAPI_ProjectPointOnSurf projection(gp_Pnt(x.x(), x.y(), x.z()), surface);
      if (projection.NbPoints() == 0)
        throw std::runtime_error("a point of the Coons patch cannot be projected onto the surface");
      deviation = std::max(deviation, projection.LowerDistance());
    }
  return deviation;
}

namespace {

std::string fail(CadFace& report, const std::string& why) {
  std::ostringstream note;
  note << "trimmed 4-sided face (1 wire, " << report.edges << " edges) whose Coons patch of the "
       << "edges is not usable: " << why
       << "; split it in the CAD program into 4-sided faces whose interior is the blend of their "
          "edges (or drop it with \"faces\")";
  report.note = note.str();
  return report.note;
}

}  // namespace

int outer_wire_edges(const TopoDS_Face& face) {
  const TopoDS_Wire wire = BRepTools::OuterWire(face);
  if (wire.IsNull()) return 0;
  int n = 0;
  for (BRepTools_WireExplorer ex(wire, face); ex.More(); ex.Next()) ++n;
  return n;
}

bool coons_face_patch(const TopoDS_Face& face, CadFace& report, nurbs::Patch& patch) {
  if (report.wires != 1 || outer_wire_edges(face) != 4) return false;
  // Edges in order around the outer wire. The wire (explored from the face) carries the face's
  // orientation, so the loop runs counter-clockwise about the face's outward normal.
  std::vector<nurbs::Patch> loop;
  try {
    for (BRepTools_WireExplorer ex(BRepTools::OuterWire(face), face); ex.More(); ex.Next())
      loop.push_back(edge_curve(ex.Current()));
  } catch (const Standard_Failure& e) {
    fail(report, std::string("OpenCascade cannot convert an edge (") + e.GetMessageString() + ")");
    return false;
  } catch (const std::exception& e) {
    fail(report, e.what());
    return false;
  }
  // Vertex tolerances bound how far the edge ends may be from the shared corners.
  const double corner_tolerance = 2.0 * BRep_Tool::MaxTolerance(face, TopAbs_VERTEX) + 1e-12;
  try {
    // Loop c0 c1 c2 c3: S(u,0) = c0, S(1,v) = c1, S(u,1) = c2 reversed, S(0,v) = c3 reversed.
    patch = coons_patch(loop[0], loop[1], reverse_direction(loop[2], 0),
                        reverse_direction(loop[3], 0), corner_tolerance);
  } catch (const std::invalid_argument& e) {
    fail(report, e.what());
    return false;
  }
  // The Coons patch is the blend of the edges; it is the face only when its interior lies on the
  // face's surface. Check samples (projection distance), orientation (Jacobian against the
  // oriented surface normal) and the area.
  const Handle(Geom_Surface) surface = BRep_Tool::Surface(face);
  const auto [lo, hi] = patch.control_bounds();
  const double size = (hi - lo).norm();
  const double tolerance = std::max(1e-9 * size, BRep_Tool::MaxTolerance(face, TopAbs_EDGE));
  const double sign = face.Orientation() == TopAbs_REVERSED ? -1.0 : 1.0;
  double deviation = 0.0;
  int positive = 0, negative = 0;
  constexpr int kSamples = 9;  // interior grid of (kSamples - 1)^2 points
  for (int a = 1; a < kSamples; ++a)
    for (int b = 1; b < kSamples; ++b) {
      const nurbs::PatchDerivatives d = patch.derivatives(
          {static_cast<double>(a) / kSamples, static_cast<double>(b) / kSamples, 0});
      GeomAPI_ProjectPointOnSurf projection(gp_Pnt(d.point.x(), d.point.y(), d.point.z()), surface);
      if (projection.NbPoints() == 0) {
        fail(report, "a point of the Coons patch cannot be projected onto the " +
                         report.surface_type + " surface");
        return false;
      }
      deviation = std::max(deviation, projection.LowerDistance());
      double u = 0.0, v = 0.0;
      projection.LowerDistanceParameters(u, v);
      GeomLProp_SLProps props(surface, u, v, 1, 1e-12);
      if (!props.IsNormalDefined()) continue;  // singular point of the surface (pole, apex)
      const gp_Dir n = props.Normal();
      const double dot =
          sign * d.first.col(0).cross(d.first.col(1)).dot(Eigen::Vector3d(n.X(), n.Y(), n.Z()));
      (dot > 0.0 ? positive : negative) += 1;
    }
  std::ostringstream why;
  why.precision(3);
  if (deviation > tolerance) {
    why << "its interior is up to " << deviation << " m (" << deviation / size
        << " of the face size) off the " << report.surface_type << " surface";
    fail(report, why.str());
    return false;
  }
  if (positive > 0 && negative > 0) {
    fail(report, "the Coons patch folds over (its Jacobian changes sign)");
    return false;
  }
  if (negative > 0) patch = reverse_direction(patch, 0);  // defensive: keep the outward normal
  const double area = measure(patch);
  if (std::abs(area - report.area) > 1e-6 * report.area) {
    why << "its area " << area << " m^2 differs from the face area " << report.area << " m^2";
    fail(report, why.str());
    return false;
  }
  report.coons = true;
  report.coons_deviation = deviation;
  report.note.clear();
  return true;
}

// A trimmed face with one wire of four edges: the Coons patch of its edges. Only faces the natural
// recogniser explained (its note) are tried: a face it failed on for another reason threw.
FaceRecognition recognise_coons_face(const TopoDS_Face& face, CadFace& report) {
  FaceRecognition out;
  if (report.note.empty() || report.wires != 1) return out;
  nurbs::Patch patch;
  if (!coons_face_patch(face, report, patch)) return out;
  out.recognised = true;
  out.patches.push_back(std::move(patch));
  return out;
}

}  // namespace isospring::geometry::detail
