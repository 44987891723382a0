// Solids of revolution (four-sided profile, full turn) -> four exact quarter volume patches.
#include "cad_solid_recognisers.hpp"

#include <BRepAdaptor_Surface.hxx>
#include <BRepGProp.hxx>
#include <BRepTools.hxx>
#include <BRep_Tool.hxx>
#include <Eigen/Geometry>
#include <GProp_GProps.hxx>
#include <Geom_Surface.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "cad_coons.hpp"
#include "isospring/geometry/construction.hpp"
#include "isospring/geometry/coons.hpp"
#include "isospring/geometry/measure.hpp"

namespace isospring::geometry::detail {

namespace {

// Axis of a surface of revolution (false for other surfaces).
bool revolution_axis(const BRepAdaptor_Surface& s, gp_Ax1& axis) {
  switch (s.GetType()) {
    case GeomAbs_Cylinder:
      axis = s.Cylinder().Axis();
      return true;
    case GeomAbs_Cone:
      axis = s.Cone().Axis();
      return true;
    case GeomAbs_Sphere:
      axis = s.Sphere().Position().Axis();
      return true;
    case GeomAbs_Torus:
      axis = s.Torus().Axis();
      return true;
    case GeomAbs_SurfaceOfRevolution:
      axis = s.AxeOfRevolution();
      return true;
    default:
      return false;
  }
}

double wrap(double angle) {  // into (-pi, pi]
  return std::remainder(angle, 2.0 * M_PI);
}

// The solid's axis and the local frame the profile is built in: origin on the axis, z along it.
struct AxisFrame {
  gp_Ax1 axis;
  Eigen::Vector3d origin, ex, ey, ez;
  double tolerance = 0.0;  // the solid's largest edge tolerance (at least 1e-9)

  Eigen::Vector3d local(const gp_Pnt& p) const {
    const Eigen::Vector3d d = Eigen::Vector3d(p.X(), p.Y(), p.Z()) - origin;
    return Eigen::Vector3d(ex.dot(d), ey.dot(d), ez.dot(d));
  }
};

// The common axis, from the first curved face; false when no face is of revolution.
bool axis_frame(const TopoDS_Shape& solid, const TopTools_IndexedMapOfShape& faces,
                AxisFrame& frame) {
  bool found = false;
  for (int f = 1; f <= faces.Extent() && !found; ++f)
    found = revolution_axis(BRepAdaptor_Surface(TopoDS::Face(faces(f))), frame.axis);
  if (!found) return false;
  const gp_Ax1& axis = frame.axis;
  frame.origin = {axis.Location().X(), axis.Location().Y(), axis.Location().Z()};
  frame.ez = {axis.Direction().X(), axis.Direction().Y(), axis.Direction().Z()};
  const gp_Dir x_dir = gp_Ax2(axis.Location(), axis.Direction()).XDirection();
  frame.ex = {x_dir.X(), x_dir.Y(), x_dir.Z()};
  frame.ey = frame.ez.cross(frame.ex);
  frame.tolerance = std::max(1e-9, BRep_Tool::MaxTolerance(solid, TopAbs_EDGE));
  return true;
}

// The meridian of a full face of revolution about the frame's axis, in local coordinates; false
// (with why) when it turns about another axis or by less than 2 pi.
struct UVBounds {
  double u0, u1, v0, v1;
};

bool revolution_meridian(const TopoDS_Face& face, const BRepAdaptor_Surface& s,
                         const UVBounds& bounds, const gp_Ax1& face_axis, const AxisFrame& frame,
                         nurbs::Patch& meridian, std::string& why) {
  const auto [u0, u1, v0, v1] = bounds;
  const gp_Lin line(frame.axis);
  if (!face_axis.Direction().IsParallel(frame.axis.Direction(), 1e-9) ||
      line.Distance(face_axis.Location()) > frame.tolerance) {
    why = "not a solid of revolution (faces turn about different axes)";
    return false;
  }
  if (std::abs(u1 - u0 - 2.0 * M_PI) > 1e-9) {
    why = "not a full solid of revolution (a face turns by less than 2 pi)";
    return false;
  }
  // The surface's u is the angle about the axis (either sense); find u at angle 0.
  const double vm = 0.5 * (v0 + v1);
  auto angle = [&](double u) {
    const Eigen::Vector3d x = frame.local(s.Value(u, vm));
    return std::atan2(x.y(), x.x());
  };
  const double sense = wrap(angle(u0 + 0.1) - angle(u0)) > 0 ? 1.0 : -1.0;
  double u = u0 + std::fmod(sense * -angle(u0) + 4.0 * M_PI, 2.0 * M_PI);
  const Handle(Geom_Surface) surface = BRep_Tool::Surface(face);
  nurbs::Patch m = curve_patch(surface->UIso(u), v0, v1);
  std::vector<Eigen::Vector3d> points;
  for (const auto& x : m.control_points())
    points.push_back(frame.local(gp_Pnt(x.x(), x.y(), x.z())));
  meridian = nurbs::Patch(m.all_knots(), points, m.weights());
  return true;
}

// A cap across the axis: between its smallest and largest circle, a radial segment.
nurbs::Patch cap_meridian(const TopoDS_Face& face, const AxisFrame& frame) {
  TopTools_IndexedMapOfShape edges;
  TopExp::MapShapes(face, TopAbs_EDGE, edges);
  double r_min = INFINITY, r_max = 0.0, z = 0.0;
  for (int e = 1; e <= edges.Extent(); ++e) {
    const nurbs::Patch c = edge_curve(TopoDS::Edge(edges(e)));
    const Eigen::Vector3d p = c.point({c.param_min(0), 0, 0});
    const Eigen::Vector3d l = frame.local(gp_Pnt(p.x(), p.y(), p.z()));
    z = l.z();  // the cap is across the axis: every point has the same height
    const double r = std::hypot(l.x(), l.y());
    r_min = std::min(r_min, r);
    r_max = std::max(r_max, r);
  }
  TopTools_IndexedMapOfShape wires;
  TopExp::MapShapes(face, TopAbs_WIRE, wires);
  if (wires.Extent() == 1) r_min = 0.0;  // a disc: its radial segment starts on the axis
  return nurbs::Patch({nurbs::KnotVector(1, {0, 0, 1, 1})}, {{r_min, 0, z}, {r_max, 0, z}});
}

// The meridian of each face in the half-plane at angle 0 (local x >= 0, y = 0), in local
// coordinates (axis = z); false (with why) when a face is neither of revolution nor a cap, or
// OpenCascade or the conversion fails.
bool face_meridians(const TopTools_IndexedMapOfShape& faces, const AxisFrame& frame,
                    std::vector<nurbs::Patch>& meridians, std::string& why) {
  try {
    for (int f = 1; f <= faces.Extent(); ++f) {
      const TopoDS_Face face = TopoDS::Face(faces(f));
      const BRepAdaptor_Surface s(face);
      gp_Ax1 face_axis;
      UVBounds bounds;
      BRepTools::UVBounds(face, bounds.u0, bounds.u1, bounds.v0, bounds.v1);
      if (revolution_axis(s, face_axis)) {
        nurbs::Patch meridian;
        if (!revolution_meridian(face, s, bounds, face_axis, frame, meridian, why)) return false;
        meridians.push_back(meridian);
      } else if (s.GetType() == GeomAbs_Plane &&
                 s.Plane().Axis().Direction().IsParallel(frame.axis.Direction(), 1e-9)) {
        meridians.push_back(cap_meridian(face, frame));
      } else {
        why = "not a solid of revolution (a face is neither of revolution nor a cap)";
        return false;
      }
    }
  } catch (const Standard_Failure& e) {
    why = std::string("solid of revolution, but OpenCascade failed: ") + e.GetMessageString();
    return false;
  } catch (const std::exception& e) {
    why = std::string("solid of revolution, but ") + e.what();
    return false;
  }
  return true;
}

Eigen::Vector3d start_point(const nurbs::Patch& c) {
  return c.point({c.param_min(0), 0, 0});
}
Eigen::Vector3d end_point(const nurbs::Patch& c) {
  return c.point({c.param_max(0), 0, 0});
}

// One face (a torus): its closed meridian cut into four quarters of its parameter range, whose
// Coons patch is the single-patch disk (zero Jacobian at its 4 corners, like the torus
// primitive). False (with why) when the meridian is not closed.
bool quartered_meridian(std::vector<nurbs::Patch>& meridians, double tolerance, std::string& why) {
  const nurbs::Patch m = meridians[0];
  if ((start_point(m) - end_point(m)).norm() > 2 * tolerance) {
    why = "solid of revolution, but its single face's meridian is not closed";
    return false;
  }
  const double a = m.param_min(0), b = m.param_max(0);
  const auto [h0, h1] = split_patch(m, 0, a + 0.5 * (b - a));
  const auto [q0, q1] = split_patch(h0, 0, a + 0.25 * (b - a));
  const auto [q2, q3] = split_patch(h1, 0, a + 0.75 * (b - a));
  meridians = {q0, q1, q2, q3};
  return true;
}

// Chain the meridians into a loop, starting at one that touches the axis (if any); a profile of
// three meridians with both open ends on the axis is closed by the axis segment (a solid
// cylinder: the volume then has a collapsed face on the axis, like the spheroid primitive).
// False (with why) when they do not form one closed four-sided profile.
bool profile_loop(std::vector<nurbs::Patch> meridians, double tolerance,
                  std::vector<nurbs::Patch>& loop, std::string& why) {
  auto on_axis = [&](const Eigen::Vector3d& x) { return std::hypot(x.x(), x.y()) <= tolerance; };
  if (meridians.size() == 1 && !quartered_meridian(meridians, tolerance, why)) return false;
  const size_t n = meridians.size();
  size_t first = 0;
  for (size_t k = 0; k < n; ++k)
    if (on_axis(start_point(meridians[k])) || on_axis(end_point(meridians[k]))) {
      first = k;
      if (!on_axis(start_point(meridians[k]))) meridians[k] = reverse_direction(meridians[k], 0);
      break;
    }
  loop = {meridians[first]};
  std::vector<bool> used(n, false);
  used[first] = true;
  for (size_t m = 1; m < n; ++m) {
    bool linked = false;
    for (size_t k = 0; k < n && !linked; ++k) {
      if (used[k]) continue;
      if ((start_point(meridians[k]) - end_point(loop.back())).norm() <= 2 * tolerance) {
        loop.push_back(meridians[k]);
        linked = used[k] = true;
      } else if ((end_point(meridians[k]) - end_point(loop.back())).norm() <= 2 * tolerance) {
        loop.push_back(reverse_direction(meridians[k], 0));
        linked = used[k] = true;
      }
    }
    if (!linked) {
      why = "solid of revolution, but its face meridians do not form one closed profile";
      return false;
    }
  }
  if (n == 3) {
    if (!on_axis(start_point(loop.front())) || !on_axis(end_point(loop.back()))) {
      why = "solid of revolution, but its 3 face meridians do not end on the axis";
      return false;
    }
    loop.push_back(nurbs::Patch({nurbs::KnotVector(1, {0, 0, 1, 1})},
                                {end_point(loop.back()), start_point(loop.front())}));
  }
  return true;
}

// The Coons patch of the profile loop revolved a full turn about the axis, right-handed, in
// global coordinates; false (with why) when the Coons patch fails or folds.
bool revolved_profile(const std::vector<nurbs::Patch>& loop, const AxisFrame& frame,
                      nurbs::Patch& volume, std::string& why) {
  nurbs::Patch profile;
  try {
    profile = coons_patch(loop[0], loop[1], reverse_direction(loop[2], 0),
                          reverse_direction(loop[3], 0), 2 * frame.tolerance);
  } catch (const std::invalid_argument& e) {
    why = std::string("solid of revolution, but its profile: ") + e.what();
    return false;
  }
  volume = revolve_about_z(profile, 2.0 * M_PI);
  const JacobianRange range = jacobian_range(volume);
  if (range.min < 0.0 && range.max < 0.0) volume = reverse_direction(volume, 1);
  if (!(jacobian_range(volume).min > 0.0)) {
    why = "solid of revolution, but the Coons patch of its profile folds";
    return false;
  }
  Eigen::Matrix3d A;
  A.col(0) = frame.ex;
  A.col(1) = frame.ey;
  A.col(2) = frame.ez;
  volume = transformed(volume, A, frame.origin);
  return true;
}

// Four quarters at the double knots of the full-turn arc (conforming, exact), each over [0, 1]
// around the axis like the primitives.
std::vector<nurbs::Patch> quarter_volumes(const nurbs::Patch& volume) {
  const auto [half0, half1] = split_patch(volume, 0, 0.5);
  const auto [q0, q1] = split_patch(half0, 0, 0.25);
  const auto [q2, q3] = split_patch(half1, 0, 0.75);
  std::vector<nurbs::Patch> quarters;
  for (const nurbs::Patch& q : {q0, q1, q2, q3}) {
    std::vector<nurbs::KnotVector> knots = q.all_knots();
    std::vector<double> t = knots[0].values();
    for (double& k : t) k = (k - q.param_min(0)) / (q.param_max(0) - q.param_min(0));
    knots[0] = nurbs::KnotVector(knots[0].degree(), t);
    quarters.emplace_back(knots, q.control_points(), q.weights());
  }
  return quarters;
}

// Every boundary side (profile side swept) must lie on a CAD face. The quarters are exact rotated
// copies of each other (same profile, same arc), so the first one is checked. False (with why)
// when a side is off the faces.
bool sides_on_faces(const nurbs::Patch& quarter, const TopTools_IndexedMapOfShape& faces,
                    const AxisFrame& frame, std::string& why) {
  const Eigen::Vector3d& O = frame.origin;
  const Eigen::Vector3d& ez = frame.ez;
  for (int dir = 1; dir < 3; ++dir)
    for (int side = 0; side < 2; ++side) {
      const nurbs::Patch face = boundary_side(quarter, dir, side);
      const Eigen::Vector3d mid = face.point({0.5 * (face.param_min(0) + face.param_max(0)),
                                              0.5 * (face.param_min(1) + face.param_max(1)), 0});
      if ((mid - O - ez * ez.dot(mid - O)).norm() <= frame.tolerance) continue;  // collapsed axis
      double best = INFINITY;
      for (int f = 1; f <= faces.Extent(); ++f)
        best = std::min(best, surface_deviation(face, TopoDS::Face(faces(f))));
      if (!(best <= frame.tolerance)) {
        std::ostringstream msg;
        msg << "solid of revolution, but a swept profile side is " << best
            << " m off the CAD faces";
        why = msg.str();
        return false;
      }
    }
  return true;
}

// The quarters' volume must be the solid's (OpenCascade's) to 1e-6; false (with why) otherwise.
bool volume_matches(const TopoDS_Shape& solid, const std::vector<nurbs::Patch>& quarters,
                    std::string& why) {
  GProp_GProps props;
  BRepGProp::VolumeProperties(solid, props, 1e-9);
  const double v = measure(quarters);
  if (std::abs(v - props.Mass()) > 1e-6 * std::abs(props.Mass())) {
    std::ostringstream msg;
    msg << "solid of revolution, but the revolved volume " << v << " m^3 differs from the solid's "
        << props.Mass() << " m^3";
    why = msg.str();
    return false;
  }
  return true;
}

// The stages in order: the axis, each face's meridian, the profile loop, its revolved Coons
// volume, the four quarters, and the checks against the CAD faces and volume.
bool revolution_patches(const TopoDS_Shape& solid, std::vector<nurbs::Patch>& patches,
                        std::string& why) {
  TopTools_IndexedMapOfShape faces;
  TopExp::MapShapes(solid, TopAbs_FACE, faces);
  AxisFrame frame;
  if (!axis_frame(solid, faces, frame)) {
    why = "not a solid of revolution (no face of revolution)";
    return false;
  }
  const int n_faces = faces.Extent();
  if (n_faces != 4 && n_faces != 3 && n_faces != 1) {
    why =
        "not a solid of revolution with a 4-sided profile (" + std::to_string(n_faces) + " faces)";
    return false;
  }
  std::vector<nurbs::Patch> meridians, loop;
  if (!face_meridians(faces, frame, meridians, why)) return false;
  if (!profile_loop(meridians, frame.tolerance, loop, why)) return false;
  nurbs::Patch volume;
  if (!revolved_profile(loop, frame, volume, why)) return false;
  const std::vector<nurbs::Patch> quarters = quarter_volumes(volume);
  if (!sides_on_faces(quarters.front(), faces, frame, why)) return false;
  if (!volume_matches(solid, quarters, why)) return false;
  patches = quarters;
  return true;
}

}  // namespace

// A solid whose faces are all full (2 pi) surfaces of revolution about one axis (cylinders,
// cones, spheres, tori, surfaces of revolution) or planes across the axis, with a four-sided
// profile: four faces (e.g. a tube), three faces whose profile is closed by the axis (e.g. a
// solid cylinder; the volume then has a collapsed face on the axis), or one face with a closed
// meridian (a torus: the meridian is cut into four arcs, whose Coons patch is the single-patch
// disk with a zero Jacobian at its four corners, as in the torus primitive). The profile (the
// faces' meridians in one half-plane, exact B-splines; caps give radial segments) becomes a planar
// Coons patch, revolved exactly with rational quarter arcs and split into four conforming 90
// degree volume patches over [0, 1] (direction 0 around the axis). Accepted when every swept side
// lies on a CAD face, the Jacobian is positive inside and the volume matches OCCT's to 1e-6;
// otherwise not recognised, with why (final when it is a solid of revolution).
SolidRecognition recognise_revolution(const SolidContext& context) {
  SolidRecognition r;
  r.recognised = revolution_patches(context.solid, r.patches, r.why);
  if (r.recognised) return r;
  // "not a (full) solid of revolution ...": say nothing, the other recognisers explain better;
  // any other reason: it is one, and what stopped it is the solid's note.
  if (r.why.rfind("not ", 0) == 0)
    r.why.clear();
  else
    r.final = true;
  return r;
}

}  // namespace isospring::geometry::detail
