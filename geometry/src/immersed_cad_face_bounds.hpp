#pragma once
// A cheap lower bound of a point's distance to a face, asked before OpenCascade's exact
// point-face distance (which on a face with many edges costs about a millisecond): the distance
// to the face's whole analytic surface (plane, cylinder, sphere, ring torus; none for other
// surfaces), as the face is part of it. A face it puts beyond a block's half-diagonal is one the
// exact distance would have put there too, so the classification decides as before.
#include <TopoDS_Face.hxx>

#include <Eigen/Core>

namespace isospring::geometry::detail {

class FaceSurfaceBound {
 public:
  explicit FaceSurfaceBound(const TopoDS_Face& face);

  /// A lower bound of the distance from x to the face (0 when none is known).
  double distance_below(const Eigen::Vector3d& x) const;

 private:
  enum class Kind { kNone, kPlane, kCylinder, kSphere, kTorus };
  Kind kind_ = Kind::kNone;
  Eigen::Vector3d origin_ = Eigen::Vector3d::Zero(), axis_ = Eigen::Vector3d::UnitZ();
  double radius_ = 0.0, minor_ = 0.0;
};

}  // namespace isospring::geometry::detail
