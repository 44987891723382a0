// Side control points and frames.
#include "isospring/analysis/sides.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <map>

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

std::vector<std::array<bool, 6>> inner_sides(const std::vector<nurbs::Patch>& patches,
                                             const DofMap& dofs, double relative_tolerance) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (const auto& patch : patches) {
    const auto [plo, phi] = patch.control_bounds();
    lo = lo.cwiseMin(plo);
    hi = hi.cwiseMax(phi);
  }
  const double tol = patches.empty() ? 0.0 : relative_tolerance * (hi - lo).norm();
  std::vector<std::array<bool, 6>> inner(patches.size(), std::array<bool, 6>{});
  // DofMap glues whole sides only (every point of one onto a point of the other), so a glued
  // side's node set is another side's node set; sides that merely touch share fewer nodes.
  std::map<std::vector<int>, std::vector<std::pair<size_t, int>>> sides_of_nodes;
  for (size_t p = 0; p < patches.size(); ++p)
    for (int dir = 0; dir < patches[p].param_dim(); ++dir)
      for (int end = 0; end < 2; ++end) {
        std::array<int, 2> size{0, 0};
        const std::vector<int> points = side_control_points(patches[p], dir, end, &size);
        auto x = [&](int a, int b) -> const Eigen::Vector3d& {
          return patches[p].control_point(points[static_cast<size_t>(a + size[0] * b)]);
        };
        // Collapsed along the first (rows of constant b are points) or the second direction.
        bool first = true, second = true;
        for (int b = 0; b < size[1]; ++b)
          for (int a = 0; a < size[0]; ++a) {
            first = first && (x(a, b) - x(0, b)).norm() <= tol;
            second = second && (x(a, b) - x(a, 0)).norm() <= tol;
          }
        // A curve's end (size {1, 1}) is a point by nature, not a collapsed side.
        if (size[0] * size[1] > 1 && (first || second))
          inner[p][static_cast<size_t>(2 * dir + end)] = true;
        std::vector<int> nodes;
        for (int i : points) nodes.push_back(dofs.node(static_cast<int>(p), i));
        std::sort(nodes.begin(), nodes.end());
        sides_of_nodes[nodes].push_back({p, 2 * dir + end});
      }
  for (const auto& [nodes, sides] : sides_of_nodes)
    if (sides.size() > 1)
      for (const auto& [p, side] : sides) inner[p][static_cast<size_t>(side)] = true;
  return inner;
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
