// Face selectors (see cad_face_selection.hpp): pure geometry on the faces' sample points.
#include "isospring/geometry/cad_face_selection.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "isospring/nurbs/error.hpp"

namespace isospring::geometry {
namespace {

using nurbs::InputError;

bool on_plane(const Eigen::Vector3d& x, const FaceSelector& s, const Eigen::Vector3d& n) {
  return std::abs(n.dot(x - s.point)) <= s.tolerance;
}

bool in_box(const Eigen::Vector3d& x, const FaceSelector& s) {
  return ((x - s.box_min).array() >= -s.tolerance).all() &&
         ((s.box_max - x).array() >= -s.tolerance).all();
}

bool on_cylinder(const Eigen::Vector3d& x, const FaceSelector& s, const Eigen::Vector3d& a) {
  const Eigen::Vector3d r = x - s.point;
  return std::abs((r - r.dot(a) * a).norm() - s.radius) <= s.tolerance;
}

void check(const FaceSelector& s) {
  if (!(s.tolerance >= 0.0 && std::isfinite(s.tolerance)))
    throw InputError("face selector: tolerance must be a non-negative length in m");
  switch (s.kind) {
    case FaceSelector::Kind::kPlane:
      if (!(s.direction.norm() > 0.0))
        throw InputError("face selector: the plane's normal is zero; give its direction");
      break;
    case FaceSelector::Kind::kCylinder:
      if (!(s.direction.norm() > 0.0))
        throw InputError("face selector: the cylinder's axis is zero; give its direction");
      if (!(s.radius >= 0.0)) throw InputError("face selector: the radius must be >= 0 m");
      break;
    case FaceSelector::Kind::kBox:
      if (!(s.box_min.array() <= s.box_max.array()).all())
        throw InputError("face selector: the box's min exceeds its max in some direction");
      break;
    case FaceSelector::Kind::kName:
      if (s.name.empty()) throw InputError("face selector: the name is empty");
      break;
  }
}

std::string vec(const Eigen::Vector3d& v) {
  std::ostringstream out;
  out << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return out.str();
}

}  // namespace

std::vector<int> select_faces(const std::vector<SolidFace>& faces, const FaceSelector& s) {
  check(s);
  const Eigen::Vector3d unit = s.direction.norm() > 0 ? s.direction.normalized() : s.direction;
  std::vector<int> chosen;
  for (const SolidFace& f : faces) {
    bool match = !f.samples.empty();
    if (s.kind == FaceSelector::Kind::kName) {
      match = f.name == s.name;
    } else {
      for (const Eigen::Vector3d& x : f.samples) {
        match = match && (s.kind == FaceSelector::Kind::kPlane ? on_plane(x, s, unit)
                          : s.kind == FaceSelector::Kind::kBox ? in_box(x, s)
                                                               : on_cylinder(x, s, unit));
        if (!match) break;
      }
    }
    if (match) chosen.push_back(f.index);
  }
  std::sort(chosen.begin(), chosen.end());
  return chosen;
}

std::string describe(const FaceSelector& s) {
  std::ostringstream out;
  switch (s.kind) {
    case FaceSelector::Kind::kPlane:
      out << "plane through " << vec(s.point) << " normal " << vec(s.direction);
      break;
    case FaceSelector::Kind::kBox:
      out << "box " << vec(s.box_min) << " .. " << vec(s.box_max);
      break;
    case FaceSelector::Kind::kCylinder:
      out << "cylinder of radius " << s.radius << " m about the axis through " << vec(s.point)
          << " along " << vec(s.direction);
      break;
    case FaceSelector::Kind::kName:
      return "name '" + s.name + "'";
  }
  out << ", tolerance " << s.tolerance << " m";
  return out.str();
}

}  // namespace isospring::geometry
