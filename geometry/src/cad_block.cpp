// Orthogonal solids with through-holes -> conforming volume patches (see cad_block.hpp).
#include "cad_solid_recognisers.hpp"

#include <BRepAdaptor_Surface.hxx>
#include <BRepClass3d_SolidClassifier.hxx>
#include <BRepTools.hxx>
#include <BRepTools_WireExplorer.hxx>
#include <BRep_Tool.hxx>
#include <Eigen/Geometry>
#include <Standard_Failure.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Wire.hxx>
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <sstream>

#include "cad_coons.hpp"
#include "isospring/geometry/block_split.hpp"
#include "isospring/geometry/construction.hpp"
#include "isospring/geometry/measure.hpp"
#include "planar_split_parts.hpp"

namespace isospring::geometry::detail {

namespace {

using Eigen::Vector3d;

Vector3d vec(const gp_Dir& d) {
  return {d.X(), d.Y(), d.Z()};
}

// One end of a hole: an inner wire of a face normal to `axis` at coordinate `level`.
struct HoleEnd {
  int axis = 0;
  double level = 0.0;
  Vector3d mid = Vector3d::Zero();  // centre of the loop's control net (pairs the two ends)
  std::vector<nurbs::Patch> loop;   // in the hole's cross plane (ThroughHole::loop)
};

constexpr double kParallel = 1e-9;

// A cylindrical face: its axis (one of the frame's), a point of the axis and its radius, in the
// frame's coordinates.
struct Cylinder {
  int axis = 0;
  Vector3d point = Vector3d::Zero();
  double radius = 0.0;
};

// The hole's loop (in its cross plane) is on the cylinder: centre on the axis, every point at
// the radius (1e-4 relative: CAD programs fit edges to 1e-5 or better; the CAx-IF L-bracket's
// degree-5 fits are 2.3e-6 off).
bool on_cylinder(const std::vector<nurbs::Patch>& loop, int b, int c, const Cylinder& cylinder) {
  for (const nurbs::Patch& curve : loop)
    for (int k = 0; k <= 16; ++k) {
      const double t = curve.param_min(0) + (curve.param_max(0) - curve.param_min(0)) * k / 16.0;
      const Vector3d x = curve.point({t, 0, 0});
      const double r = std::hypot(x.x() - cylinder.point[b], x.y() - cylinder.point[c]);
      if (std::abs(r - cylinder.radius) > 1e-4 * cylinder.radius) return false;
    }
  return true;
}

// The axis (0, 1, 2) of `frame` that `d` is parallel to, or none.
std::optional<int> axis_of(const Eigen::Matrix3d& frame, const Vector3d& d) {
  for (int q = 0; q < 3; ++q)
    if (std::abs(std::abs(frame.col(q).dot(d)) - 1.0) < kParallel) return q;
  return std::nullopt;
}

// The block's axes: the first planar face's normal and the first one normal to it (columns of
// `frame`, right-handed); false (with why) when there are no such faces.
bool block_frame(const TopoDS_Shape& solid, Eigen::Matrix3d& frame, std::string& why) {
  std::vector<Vector3d> normals;
  for (TopExp_Explorer f(solid, TopAbs_FACE); f.More(); f.Next()) {
    const BRepAdaptor_Surface s(TopoDS::Face(f.Current()));
    if (s.GetType() == GeomAbs_Plane) normals.push_back(vec(s.Plane().Axis().Direction()));
  }
  if (normals.empty()) {
    why = "not an orthogonal block (no planar face)";
    return false;
  }
  frame.col(0) = normals.front();
  const auto second = std::find_if(normals.begin(), normals.end(), [&](const Vector3d& n) {
    return std::abs(n.dot(normals.front())) < kParallel;
  });
  if (second == normals.end()) {
    why = "not an orthogonal block (no two planar faces at right angles)";
    return false;
  }
  frame.col(1) = *second;
  frame.col(2) = frame.col(0).cross(frame.col(1));
  return true;
}

// What the faces tell in the frame's coordinates: the face planes per axis, the ends of the holes
// (inner wires of the planar faces) and the cylindrical hole walls.
struct BlockFaces {
  std::array<std::vector<double>, 3> planes;  // BlockRegion::planes
  std::vector<HoleEnd> ends;
  std::vector<Cylinder> cylinders;
};

// The inner wires of a planar face normal to axis q at coordinate `level`, as hole ends. Throws
// std::runtime_error when an edge leaves the face's plane.
void add_hole_ends(const TopoDS_Face& face, int q, double level, const Eigen::Matrix3d& frame,
                   double tolerance, std::vector<HoleEnd>& ends) {
  const int b = (q + 1) % 3, c = (q + 2) % 3;
  const TopoDS_Wire outer = BRepTools::OuterWire(face);
  for (TopExp_Explorer w(face, TopAbs_WIRE); w.More(); w.Next()) {
    const TopoDS_Wire wire = TopoDS::Wire(w.Current());
    if (wire.IsSame(outer)) continue;
    HoleEnd end;
    end.axis = q;
    end.level = level;
    int points = 0;
    for (BRepTools_WireExplorer e(wire, face); e.More(); e.Next()) {
      nurbs::Patch curve = edge_curve(e.Current());
      for (int i = 0; i < curve.num_points(); ++i) {
        const Vector3d x = frame.transpose() * curve.control_point(i);
        if (std::abs(x[q] - level) > tolerance) throw std::runtime_error("an edge leaves its face");
        curve.set_control_point(i, Vector3d(x[b], x[c], 0.0));
        end.mid += Vector3d(x[b], x[c], 0.0);
        ++points;
      }
      end.loop.push_back(curve);
    }
    end.mid /= std::max(points, 1);
    ends.push_back(end);
  }
}

// Every face is a plane normal to an axis of the frame or a straight hole wall along one; false
// (with why) otherwise or when OpenCascade cannot convert an edge.
bool read_block_faces(const TopoDS_Shape& solid, const Eigen::Matrix3d& frame, double tolerance,
                      BlockFaces& out, std::string& why) {
  auto local = [&](const gp_Pnt& p) -> Vector3d {
    return frame.transpose() * Vector3d(p.X(), p.Y(), p.Z());
  };
  try {
    for (TopExp_Explorer f(solid, TopAbs_FACE); f.More(); f.Next()) {
      const TopoDS_Face face = TopoDS::Face(f.Current());
      const BRepAdaptor_Surface s(face);
      if (s.GetType() == GeomAbs_Cylinder || s.GetType() == GeomAbs_SurfaceOfExtrusion) {
        const Vector3d along =
            vec(s.GetType() == GeomAbs_Cylinder ? s.Cylinder().Axis().Direction() : s.Direction());
        const std::optional<int> axis = axis_of(frame, along);
        if (!axis) {
          why = "not an orthogonal block (a hole wall is not along the block's axes)";
          return false;
        }
        if (s.GetType() == GeomAbs_Cylinder)
          out.cylinders.push_back({*axis, local(s.Cylinder().Location()), s.Cylinder().Radius()});
        continue;  // a hole wall: the holes come from the inner wires of the planar faces
      }
      if (s.GetType() != GeomAbs_Plane) {
        why = "not an orthogonal block (a face is neither planar nor a straight hole wall)";
        return false;
      }
      const std::optional<int> axis = axis_of(frame, vec(s.Plane().Axis().Direction()));
      if (!axis) {
        why = "not an orthogonal block (a planar face is slanted)";
        return false;
      }
      const int q = *axis;
      const double level = local(s.Plane().Location())[q];
      out.planes[static_cast<size_t>(q)].push_back(level);
      add_hole_ends(face, q, level, frame, tolerance, out.ends);
    }
  } catch (const Standard_Failure& e) {
    why = std::string("not an orthogonal block (OpenCascade cannot convert an edge: ") +
          e.GetMessageString() + ")";
    return false;
  } catch (const std::exception& e) {
    why = std::string("not an orthogonal block (") + e.what() + ")";
    return false;
  }
  return true;
}

// The hole from `entry` to `exit` (ends of one hole, entry.level < exit.level). A hole whose wall
// is a cylinder is built from the cylinder, exactly: CAD programs may store its edges as
// polynomial fits (the CAx-IF L-bracket: degree 5, 4.6e-6 short of the circle's area at one end,
// exact arcs at the other).
ThroughHole through_hole(const HoleEnd& entry, const HoleEnd& exit,
                         const std::vector<Cylinder>& cylinders) {
  ThroughHole hole;
  hole.axis = entry.axis;
  hole.from = entry.level;
  hole.to = exit.level;
  hole.loop = entry.loop;
  const int b = (hole.axis + 1) % 3, c = (hole.axis + 2) % 3;
  for (const Cylinder& cylinder : cylinders)
    if (cylinder.axis == hole.axis && on_cylinder(entry.loop, b, c, cylinder) &&
        on_cylinder(exit.loop, b, c, cylinder)) {
      hole.loop = {circular_arc(Vector3d(cylinder.point[b], cylinder.point[c], 0.0),
                                cylinder.radius, 0.0, 2.0 * M_PI)};
      break;
    }
  return hole;
}

// The ends of one hole: inner wires of faces normal to one axis with the same loop centre, paired
// in order along it (a bore through two walls has four ends). Adds to `allowance` [m^3] the
// file's own disagreement between each hole's ends (and the loop used), times its length:
// OpenCascade's volume of such a solid is uncertain by as much. False (with why) when a hole ends
// inside the solid.
bool pair_hole_ends(const BlockFaces& faces, double tolerance, std::vector<ThroughHole>& holes,
                    double& allowance, std::string& why) {
  const std::vector<HoleEnd>& ends = faces.ends;
  std::vector<bool> used(ends.size(), false);
  for (size_t i = 0; i < ends.size(); ++i) {
    if (used[i]) continue;
    std::vector<size_t> same;
    for (size_t j = i; j < ends.size(); ++j)
      if (!used[j] && ends[j].axis == ends[i].axis &&
          (ends[j].mid - ends[i].mid).norm() <=
              1e-6 * std::max(1.0, ends[i].mid.norm()) + tolerance)
        same.push_back(j);
    if (same.size() % 2 != 0) {
      why = "not a block with through-holes (a hole ends inside the solid)";
      return false;
    }
    std::sort(same.begin(), same.end(),
              [&](size_t a, size_t b) { return ends[a].level < ends[b].level; });
    for (size_t k = 0; k < same.size(); k += 2) {
      const HoleEnd &entry = ends[same[k]], &exit = ends[same[k + 1]];
      const ThroughHole hole = through_hole(entry, exit, faces.cylinders);
      const double used = planar_split_detail::enclosed_area(hole.loop);
      const double spread =
          std::max(std::abs(planar_split_detail::enclosed_area(entry.loop) - used),
                   std::abs(planar_split_detail::enclosed_area(exit.loop) - used));
      allowance += spread * (hole.to - hole.from);
      holes.push_back(hole);
    }
    for (size_t j : same) used[j] = true;
  }
  return true;
}

// The region cut into conforming patches (split_block_region, inside test by OpenCascade's
// classifier), back in global coordinates; false (with why) when it cannot be cut or a patch has
// a Jacobian <= 0.
bool cut_block(const TopoDS_Shape& solid, const Eigen::Matrix3d& frame, double tolerance,
               BlockRegion& region, std::vector<nurbs::Patch>& cut, std::string& why) {
  BRepClass3d_SolidClassifier classifier(solid);
  region.inside = [&](const Vector3d& x) {
    const Vector3d p = frame * x;
    classifier.Perform(gp_Pnt(p.x(), p.y(), p.z()), tolerance);
    return classifier.State() == TopAbs_IN;
  };
  try {
    cut = split_block_region(region, tolerance);
  } catch (const std::exception& e) {
    why = std::string("an orthogonal block with through-holes, but it cannot be cut: ") + e.what();
    return false;
  }
  for (nurbs::Patch& p : cut) p = transformed(p, frame, Vector3d::Zero());
  for (size_t p = 0; p < cut.size(); ++p)
    if (!(jacobian_range(cut[p], 4).min > 0.0)) {
      why = "an orthogonal block with through-holes, but patch " + std::to_string(p) +
            " of its cut has a Jacobian <= 0";
      return false;
    }
  return true;
}

// The cut's volume must be OpenCascade's to 1e-9, or to within `allowance` (then `remark` says
// so; otherwise it is cleared); false (with why) otherwise.
bool block_volume_matches(const std::vector<nurbs::Patch>& cut, double volume, double allowance,
                          std::string& why, std::string& remark) {
  const double measured = measure(cut);
  const double mismatch = std::abs(measured - volume);
  std::ostringstream out;
  out.precision(3);
  if (!(mismatch <= 1e-9 * volume + allowance)) {
    out.precision(12);
    out << "an orthogonal block with through-holes, but its " << cut.size() << " patches' volume "
        << measured << " m^3 differs from the solid's " << volume << " m^3";
    why = out.str();
    return false;
  }
  remark.clear();
  if (mismatch > 1e-9 * volume) {
    out << "the volume differs from OpenCascade's by " << mismatch / volume
        << " (relative), within the " << allowance / volume
        << " by which the file's holes disagree between their two ends (edge curves fitted "
           "by the CAD program); the holes are built from their cylindrical walls";
    remark = out.str();
  }
  return true;
}

// The stages in order: the block's axes, its faces (planes, hole ends, hole walls), the holes,
// the cut, and the check against OpenCascade's volume.
bool block_patches(const TopoDS_Shape& solid, double volume, std::vector<nurbs::Patch>& patches,
                   std::string& why, std::string& remark) {
  const double tolerance = std::max(4.0 * BRep_Tool::MaxTolerance(solid, TopAbs_VERTEX), 1e-9);
  Eigen::Matrix3d frame;
  if (!block_frame(solid, frame, why)) return false;
  BlockFaces faces;
  if (!read_block_faces(solid, frame, tolerance, faces, why)) return false;
  BlockRegion region;
  region.planes = faces.planes;
  double allowance = 0.0;  // m^3
  if (!pair_hole_ends(faces, tolerance, region.holes, allowance, why)) return false;
  std::vector<nurbs::Patch> cut;
  if (!cut_block(solid, frame, tolerance, region, cut, why)) return false;
  if (!block_volume_matches(cut, volume, allowance, why, remark)) return false;
  patches = std::move(cut);
  return true;
}

}  // namespace

// When every planar face of the solid is normal to one of three orthogonal axes, every other
// face is the wall of a straight hole along one of them, and each hole runs from an inner wire
// of one face to an inner wire of a parallel face, the solid's conforming volume patches
// (split_block_region) with positive Jacobians (sampled 4 per element and direction) and
// `volume` (OpenCascade's) matched to 1e-9, or to within what the file's holes disagree
// between their two ends times their length (then `remark` says so; otherwise it is empty). A
// hole whose wall is a cylinder is built from the cylinder, exactly. Otherwise not recognised, with
// why.
SolidRecognition recognise_block(const SolidContext& context) {
  SolidRecognition r;
  r.recognised = block_patches(context.solid, context.volume, r.patches, r.why, r.remark);
  return r;
}

}  // namespace isospring::geometry::detail
