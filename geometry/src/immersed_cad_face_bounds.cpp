// Face-distance bounds from analytic surfaces (immersed_cad_face_bounds.hpp).
#include "immersed_cad_face_bounds.hpp"

#include <BRepAdaptor_Surface.hxx>
#include <gp_Cylinder.hxx>
#include <gp_Pln.hxx>
#include <gp_Sphere.hxx>
#include <gp_Torus.hxx>

#include <cmath>

namespace isospring::geometry::detail {

namespace {

Eigen::Vector3d to_eigen(const gp_XYZ& p) {
  return {p.X(), p.Y(), p.Z()};
}

}  // namespace

FaceSurfaceBound::FaceSurfaceBound(const TopoDS_Face& face) {
  // The adaptor applies the face's location: the surfaces are where the face is.
  const BRepAdaptor_Surface surface(face);
  switch (surface.GetType()) {
    case GeomAbs_Plane: {
      const gp_Ax3 frame = surface.Plane().Position();
      kind_ = Kind::kPlane;
      origin_ = to_eigen(frame.Location().XYZ());
      axis_ = to_eigen(frame.Direction().XYZ());
      break;
    }
    case GeomAbs_Cylinder: {
      const gp_Cylinder c = surface.Cylinder();
      kind_ = Kind::kCylinder;
      origin_ = to_eigen(c.Location().XYZ());
      axis_ = to_eigen(c.Axis().Direction().XYZ());
      radius_ = c.Radius();
      break;
    }
    case GeomAbs_Sphere: {
      const gp_Sphere s = surface.Sphere();
      kind_ = Kind::kSphere;
      origin_ = to_eigen(s.Location().XYZ());
      radius_ = s.Radius();
      break;
    }
    case GeomAbs_Torus: {
      const gp_Torus t = surface.Torus();
      kind_ = Kind::kTorus;
      origin_ = to_eigen(t.Location().XYZ());
      axis_ = to_eigen(t.Axis().Direction().XYZ());
      radius_ = t.MajorRadius();
      minor_ = t.MinorRadius();
      break;
    }
    default:
      break;
  }
}

double FaceSurfaceBound::distance_below(const Eigen::Vector3d& x) const {
  const Eigen::Vector3d r = x - origin_;
  switch (kind_) {
    case Kind::kPlane:
      return std::abs(axis_.dot(r));
    case Kind::kCylinder:  // every surface point is `radius` from the axis
      return std::abs((r - axis_.dot(r) * axis_).norm() - radius_);
    case Kind::kSphere:
      return std::abs(r.norm() - radius_);
    case Kind::kTorus: {
      // Distance to the centre circle d; every surface point of a ring torus (major >= minor)
      // is `minor` from that circle, so |d - minor| bounds the distance below; on a spindle
      // torus surface points are at most `minor` from it, so only d - minor does.
      const double h = axis_.dot(r);
      const double d = std::hypot((r - h * axis_).norm() - radius_, h);
      return radius_ >= minor_ ? std::abs(d - minor_) : std::max(0.0, d - minor_);
    }
    case Kind::kNone:
      break;
  }
  return 0.0;
}

}  // namespace isospring::geometry::detail
