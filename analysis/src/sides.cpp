// Side control points and frames.
#include "isospring/analysis/sides.hpp"

#include <Eigen/Geometry>

namespace isospring::analysis {

std::vector<int> side_control_points(const nurbs::Patch& patch, int dir, int end,
                                     std::array<int, 2>* grid_size) {
  std::array<int, 2> others{-1, -1};
  int count = 0;
  for (int d = 0; d < 3; ++d)
    if (d != dir && count < 2) others[static_cast<size_t>(count++)] = d;
  const int na = patch.num_points(others[0]);
  const int nb = patch.num_points(others[1]);
  const int fixed = end == 0 ? 0 : patch.num_points(dir) - 1;
  std::vector<int> indices;
  indices.reserve(static_cast<size_t>(na * nb));
  for (int b = 0; b < nb; ++b)
    for (int a = 0; a < na; ++a) {
      std::array<int, 3> ijk{0, 0, 0};
      ijk[static_cast<size_t>(dir)] = fixed;
      ijk[static_cast<size_t>(others[0])] = a;
      ijk[static_cast<size_t>(others[1])] = b;
      indices.push_back(patch.index(ijk[0], ijk[1], ijk[2]));
    }
  if (grid_size) *grid_size = {na, nb};
  return indices;
}

SideFrame side_frame(const Eigen::Matrix3d& jacobian, int param_dim, int dir, int end) {
  SideFrame frame;
  // dX/du_dir points into the patch at end 0 and out of it at end 1: it fixes the orientation.
  const Eigen::Vector3d inward =
      end == 0 ? Eigen::Vector3d(jacobian.col(dir)) : Eigen::Vector3d(-jacobian.col(dir));
  Eigen::Vector3d normal;
  if (param_dim == 2) {
    const Eigen::Vector3d tangent = jacobian.col(1 - dir);
    frame.measure = tangent.norm();
    normal = Eigen::Vector3d(tangent.y(), -tangent.x(), 0.0);
  } else {
    const int a = dir == 0 ? 1 : 0;
    const int b = dir == 2 ? 1 : 2;
    normal = jacobian.col(a).cross(jacobian.col(b));
    frame.measure = normal.norm();
  }
  const double length = normal.norm();
  if (length == 0.0) return frame;
  normal /= length;
  if (normal.dot(inward) > 0.0) normal = -normal;
  frame.normal = normal;
  return frame;
}

}  // namespace isospring::analysis
