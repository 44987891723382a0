#pragma once
// Point inversion: the parameter of the point on a patch closest to a given point.
#include <optional>

#include "isospring/nurbs/patch.hpp"

namespace isospring::nurbs {

struct Inversion {
  Param param{0.0, 0.0, 0.0};
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // patch point at `param`
  double distance = 0.0;
  bool converged = false;
  int iterations = 0;
};

/// Closest point on `patch` to `x` by projected Newton iteration on |X(u) - x|^2 inside the
/// parameter box. Without a start, a grid of samples (several per element) picks a robust one.
Inversion invert_point(const Patch& patch, const Eigen::Vector3d& x,
                       std::optional<Param> start = std::nullopt, double tolerance = 1e-12);

}  // namespace isospring::nurbs
