// The natural face recogniser: a face that covers its whole UV rectangle is its own NURBS patch,
// converted exactly by OpenCascade and checked against OpenCascade's evaluation.
#include <BRepBuilderAPI_NurbsConvert.hxx>
#include <BRepTools.hxx>
#include <BRep_Tool.hxx>
#include <GeomConvert.hxx>
#include <Geom_BSplineSurface.hxx>
#include <TopLoc_Location.hxx>
#include <TopoDS.hxx>
#include <cmath>
#include <random>
#include <sstream>
#include <stdexcept>

#include "cad_face_recognisers.hpp"
#include "isospring/geometry/construction.hpp"
#include "isospring/geometry/measure.hpp"
#include "occt_conversion.hpp"

namespace isospring::geometry::detail {

namespace {

// The face as a patch when it covers its whole UV rectangle; otherwise an explanation.
bool natural_patch(const TopoDS_Face& face, CadFace& report, nurbs::Patch& patch) {
  const TopoDS_Face nurbs_face = TopoDS::Face(BRepBuilderAPI_NurbsConvert(face, true).Shape());
  // The face may carry a location (IGES unit scaling, assembly placement): convert the bare
  // surface and apply the transformation to the control points (exact for NURBS).
  TopLoc_Location location;
  Handle(Geom_BSplineSurface) surface =
      GeomConvert::SurfaceToBSplineSurface(BRep_Tool::Surface(nurbs_face, location));
  surface = Handle(Geom_BSplineSurface)::DownCast(surface->Copy());
  double u0, u1, v0, v1;
  BRepTools::UVBounds(nurbs_face, u0, u1, v0, v1);
  if (surface->IsUPeriodic()) surface->SetUNotPeriodic();
  if (surface->IsVPeriodic()) surface->SetVNotPeriodic();
  // Non-periodic OCCT surfaces may still have unclamped end knots (periodic origin); raising the
  // face's bounds to full multiplicity and cutting there gives a clamped, exact patch.
  surface->InsertUKnot(u0, surface->UDegree(), 1e-12, false);
  surface->InsertUKnot(u1, surface->UDegree(), 1e-12, false);
  surface->InsertVKnot(v0, surface->VDegree(), 1e-12, false);
  surface->InsertVKnot(v1, surface->VDegree(), 1e-12, false);
  surface->Segment(u0, u1, v0, v1);
  patch = detail::patch_from_occt(surface);
  // The conversion is exact; check it by sampling against OCCT's own evaluation.
  std::mt19937 rng(1);
  const auto [lo, hi] = patch.control_bounds();
  const double size = (hi - lo).norm();
  for (int n = 0; n < 16; ++n) {
    const double u = std::uniform_real_distribution<double>(u0, u1)(rng);
    const double v = std::uniform_real_distribution<double>(v0, v1)(rng);
    const gp_Pnt p = surface->Value(u, v);
    if ((patch.point({u, v, 0}) - Eigen::Vector3d(p.X(), p.Y(), p.Z())).norm() > 1e-9 * size)
      throw std::runtime_error("face " + std::to_string(report.index) +
                               ": NURBS conversion does not reproduce the surface");
  }
  if (!location.IsIdentity()) {
    const gp_Trsf trsf = location.Transformation();
    std::vector<Eigen::Vector3d> points;
    for (const auto& x : patch.control_points()) {
      gp_XYZ p(x.x(), x.y(), x.z());
      trsf.Transforms(p);
      points.emplace_back(p.X(), p.Y(), p.Z());
    }
    patch = nurbs::Patch(patch.all_knots(), points, patch.weights());
  }
  if (face.Orientation() == TopAbs_REVERSED) patch = reverse_direction(patch, 0);
  // Natural boundary: one wire and the face's area equals the area of the whole patch.
  const double patch_area = measure(patch);
  if (report.wires != 1 || std::abs(patch_area - report.area) > 1e-6 * patch_area) {
    std::ostringstream note;
    note << "trimmed: " << report.wires << " wire(s), " << report.edges
         << " edges, face area / patch area = " << report.area / patch_area
         << "; split it into 4-sided faces in the CAD program (or drop it with \"faces\")";
    report.note = note.str();
    return false;
  }
  return true;
}

}  // namespace

FaceRecognition recognise_natural_face(const TopoDS_Face& face, CadFace& report) {
  FaceRecognition out;
  nurbs::Patch patch;
  report.natural = natural_patch(face, report, patch);
  if (!report.natural) return out;
  out.recognised = true;
  out.patches.push_back(std::move(patch));
  return out;
}

}  // namespace isospring::geometry::detail
