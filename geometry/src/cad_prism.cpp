// Prismatic solids -> the patches of their base face extruded (exact: a linear sweep).
#include "cad_solid_recognisers.hpp"

#include <BRepAdaptor_Surface.hxx>
#include <BRepGProp.hxx>
#include <BRep_Tool.hxx>
#include <GProp_GProps.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Vertex.hxx>
#include <cmath>
#include <limits>
#include <sstream>

#include "isospring/geometry/construction.hpp"
#include "isospring/geometry/measure.hpp"

namespace isospring::geometry::detail {

namespace {

double face_area(const TopoDS_Face& face) {
  GProp_GProps props;
  BRepGProp::SurfaceProperties(face, props, 1e-9);
  return props.Mass();
}

// Why the solid is not the prism of `base` (empty when it is); sets the depth t.
std::string not_prism_of(const TopoDS_Shape& solid, const TopoDS_Face& base, gp_Dir& normal,
                         double& depth) {
  const BRepAdaptor_Surface surface(base);
  const gp_Pln plane = surface.Plane();
  normal = plane.Axis().Direction();
  if (base.Orientation() == TopAbs_REVERSED) normal.Reverse();
  const gp_Pnt origin = plane.Location();
  auto height = [&](const gp_Pnt& p) { return gp_Vec(origin, p).Dot(gp_Vec(normal)); };
  const double tolerance = std::max(4.0 * BRep_Tool::MaxTolerance(solid, TopAbs_VERTEX), 1e-9);
  TopTools_IndexedMapOfShape vertices;
  TopExp::MapShapes(solid, TopAbs_VERTEX, vertices);
  depth = 0.0;
  for (int v = 1; v <= vertices.Extent(); ++v)
    depth = std::max(depth, -height(BRep_Tool::Pnt(TopoDS::Vertex(vertices(v)))));
  if (depth <= tolerance) return "the solid does not lie behind the face";
  for (int v = 1; v <= vertices.Extent(); ++v) {
    const double h = height(BRep_Tool::Pnt(TopoDS::Vertex(vertices(v))));
    if (std::abs(h) > tolerance && std::abs(h + depth) > tolerance)
      return "a vertex lies between the face and the opposite side";
  }
  int caps = 0;
  for (TopExp_Explorer f(solid, TopAbs_FACE); f.More(); f.Next()) {
    const TopoDS_Face face = TopoDS::Face(f.Current());
    if (face.IsSame(base)) continue;
    const BRepAdaptor_Surface s(face);
    constexpr double kParallel = 1e-9;
    switch (s.GetType()) {
      case GeomAbs_Plane: {
        const double c = s.Plane().Axis().Direction().Dot(normal);
        if (std::abs(c) < kParallel) break;  // a side wall
        if (std::abs(std::abs(c) - 1.0) > kParallel) return "a planar side is slanted";
        if (std::abs(height(s.Plane().Location()) + depth) > tolerance)
          return "a face parallel to it is not at the far side";
        // The same face up to the fitting tolerance of the CAD program's edge curves (the
        // volume check below is the exact one).
        if (std::abs(face_area(face) - face_area(base)) > 1e-6 * face_area(base))
          return "the far side is not the same face";
        ++caps;
        break;
      }
      case GeomAbs_Cylinder:
        if (std::abs(std::abs(s.Cylinder().Axis().Direction().Dot(normal)) - 1.0) > kParallel)
          return "a cylindrical side is not along the face normal";
        break;
      case GeomAbs_SurfaceOfExtrusion:
        if (std::abs(std::abs(s.Direction().Dot(normal)) - 1.0) > kParallel)
          return "a side is not swept along the face normal";
        break;
      default:
        return "a side is neither planar, cylindrical nor swept";
    }
  }
  if (caps != 1) return "there is no single far side";
  return "";
}

bool prism_patches(const TopoDS_Shape& solid, const FacePatches& face_patches, double volume,
                   std::vector<nurbs::Patch>& patches, std::string& why) {
  // Every planar face that passes the topological test is a candidate base; the far cap of a
  // CAD prism may differ from the base by the fitting tolerance of its edge curves (CAx-IF
  // plate: 2.5e-9 of the area), so the base whose extrusion matches the solid best is taken.
  std::string first_why;
  double best = std::numeric_limits<double>::infinity();
  for (TopExp_Explorer f(solid, TopAbs_FACE); f.More(); f.Next()) {
    const TopoDS_Face base = TopoDS::Face(f.Current());
    if (BRepAdaptor_Surface(base).GetType() != GeomAbs_Plane) continue;
    gp_Dir normal;
    double depth = 0.0;
    const std::string not_prism = not_prism_of(solid, base, normal, depth);
    if (!not_prism.empty()) {
      if (first_why.empty()) first_why = not_prism;
      continue;
    }
    const std::vector<nurbs::Patch> base_patches = face_patches(base);
    if (base_patches.empty()) {
      if (first_why.empty()) first_why = "a prism, but its base face did not become patches";
      continue;
    }
    // Extruding a planar patch by t along its normal gives det J = |X_u x X_v| t exactly, so the
    // volume is t times the base's area (and the volume patches' Jacobians are checked below).
    const double measured = depth * measure(base_patches);
    const double mismatch = std::abs(measured - volume) / volume;
    if (mismatch >= best) continue;
    // Into the solid: against the outward normal.
    const Eigen::Vector3d offset = -depth * Eigen::Vector3d(normal.X(), normal.Y(), normal.Z());
    std::vector<nurbs::Patch> volumes;
    try {
      for (const nurbs::Patch& p : base_patches)
        volumes.push_back(with_positive_jacobian(extrude(p, offset)));
    } catch (const std::exception& e) {
      if (first_why.empty())
        first_why = std::string("a prism, but its extrusion failed: ") + e.what();
      continue;
    }
    best = mismatch;
    if (mismatch <= 1e-9) {
      patches = volumes;
    } else {
      std::ostringstream out;
      out.precision(12);
      out << "a prism, but the extruded patches' volume " << measured
          << " m^3 differs from the solid's " << volume << " m^3 by " << mismatch << " (> 1e-9)";
      first_why = out.str();
    }
  }
  if (best <= 1e-9) return true;
  why = "not a prism of a planar face (" + (first_why.empty() ? "no planar face" : first_why) + ")";
  return false;
}

}  // namespace

// When the solid is a prism of one of its planar faces (every vertex on that face's plane or on
// one parallel plane at depth t, every other face either that opposite cap, with the same area,
// or a plane/cylinder/extrusion containing the normal direction), the volume patches of the
// face's patches extruded by t into the solid, right-handed, and `volume` (OpenCascade's) matched
// to 1e-9. Otherwise not recognised, with why.
SolidRecognition recognise_prism(const SolidContext& context) {
  SolidRecognition r;
  r.recognised =
      prism_patches(context.solid, context.face_patches, context.volume, r.patches, r.why);
  return r;
}

}  // namespace isospring::geometry::detail
