#pragma once
// Cheap answers to "can this face come near that box?" from the face's underlying analytic
// surface, asked before OpenCascade's exact point-face distance (which on a face with many edges
// costs about a millisecond). Both are exact statements about the face, so the classification
// they shortcut decides as the distance would:
// - a lower bound of a point's distance to the face: its distance to the whole surface (plane,
//   cylinder, sphere, ring torus; none for other surfaces), as the face is part of it;
// - a planar face whose plane does not cut the open box (it lies in or beyond one of the box's
//   faces) does not meet the open box. The faces of a part on the grid's planes
//   (its extreme faces on the grid's boundary, faces on interior grid planes) made every cell
//   next to them a cut candidate, whose lines then found no cut.
#include <TopoDS_Face.hxx>

#include <Eigen/Core>

namespace isospring::geometry::detail {

class FaceSurfaceBound {
 public:
  explicit FaceSurfaceBound(const TopoDS_Face& face);

  /// A lower bound of the distance from x to the face (0 when none is known).
  double distance_below(const Eigen::Vector3d& x) const;
  /// True when a planar face cannot meet the open box (lo, hi): over the box's cross-section its
  /// plane stays at or beyond one of the box's faces normal to the plane's main axis k (within
  /// `slack` of that face at most).
  bool misses_open_box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double slack) const;

 private:
  enum class Kind { kNone, kPlane, kCylinder, kSphere, kTorus };
  Kind kind_ = Kind::kNone;
  Eigen::Vector3d origin_ = Eigen::Vector3d::Zero(), axis_ = Eigen::Vector3d::UnitZ();
  double radius_ = 0.0, minor_ = 0.0;
  int normal_axis_ = 2;  // a plane's largest normal component
};

}  // namespace isospring::geometry::detail
