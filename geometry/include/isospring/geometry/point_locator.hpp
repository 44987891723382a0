#pragma once
// Closest-point location of arbitrary 3D points on a NURBS model (markers of measured data).
//
// Each patch is tessellated (surfaces: the patch itself; volumes: its six boundary sides) and put
// in a CGAL AABB tree; the closest tessellation point gives a starting parameter, which
// nurbs::invert_point refines on the exact NURBS. Points inside a volume patch are located by
// inversion inside the volume (distance 0).
#include <Eigen/Core>
#include <memory>
#include <vector>

#include "isospring/nurbs/patch.hpp"

namespace isospring::geometry {

struct Location {
  int patch = -1;
  nurbs::Param param{0.0, 0.0, 0.0};
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // closest point on the model
  double distance = 0.0;                            // |point - query|
  bool inside = false;                              // inside a volume patch
};

class PointLocator {
 public:
  /// Curves (param_dim 1) are not supported (std::invalid_argument). `samples_per_element` sets
  /// the tessellation density per element and direction.
  explicit PointLocator(const std::vector<nurbs::Patch>& patches, int samples_per_element = 8);
  ~PointLocator();
  PointLocator(PointLocator&&) noexcept;
  PointLocator& operator=(PointLocator&&) noexcept;

  /// The closest point of the model to x (over all patches).
  Location locate(const Eigen::Vector3d& x) const;

  /// Locates every point; `far` lists the indices whose distance exceeds `tolerance`.
  struct Batch {
    std::vector<Location> locations;
    std::vector<int> far;
  };
  Batch locate_all(const std::vector<Eigen::Vector3d>& points, double tolerance) const;

  /// Size of the model (diagonal of the control bounding box), for relative tolerances.
  double model_size() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace isospring::geometry
