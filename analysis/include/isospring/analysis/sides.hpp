#pragma once
// Control points and geometry of a patch side (the boundary where one parameter is at an end).
#include <Eigen/Core>
#include <array>
#include <vector>

#include "isospring/analysis/dof_map.hpp"
#include "isospring/analysis/problem.hpp"

namespace isospring::analysis {

/// Indices of the control points on side (dir, end), as a grid: the remaining parametric
/// directions in increasing order, the first of them fastest. `grid_size` gets the grid shape
/// ({n, 1} for the side of a surface, {1, 1} for the end of a curve).
std::vector<int> side_control_points(const nurbs::Patch& patch, int dir, int end,
                                     std::array<int, 2>* grid_size = nullptr);

/// Outward unit normal of a side at a parameter on it, and the measure factor of the side
/// (|dX/du_a| for a curve side of a surface, |dX/du_a x dX/du_b| for a surface side of a volume).
/// The normal is zero where the side is degenerate (collapsed edge or pole).
struct SideFrame {
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  double measure = 0.0;
};
/// Sides that are not part of the model's outer surface, indexed [p][2 * dir + end] (entries
/// beyond a patch's parametric dimension are false):
/// - glued sides: the control points map to exactly the nodes of another side under `dofs` (an
///   interface between patches, or the seam of a closed patch);
/// - collapsed sides: every row of the side's control grid in one of its two directions is a
///   single point (to `relative_tolerance` times the model's control-net diagonal), so the side
///   has no area; e.g. the axis of a revolved solid, which lies inside it, or a pole.
std::vector<std::array<bool, 6>> inner_sides(const std::vector<nurbs::Patch>& patches,
                                             const DofMap& dofs, double relative_tolerance = 1e-6);

SideFrame side_frame(const Eigen::Matrix3d& parametric_jacobian, int param_dim, int dir, int end);

}  // namespace isospring::analysis
