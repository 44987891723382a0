#pragma once
// Global numbering: every control point of every patch maps to a node; coincident control
// points on matching sides of different patches (conforming interfaces) share one node. A node
// carries dofs_per_node displacement components: global DOF = node * dofs_per_node + component.
#include <vector>

#include "isospring/analysis/problem.hpp"

namespace isospring::analysis {

/// 2 for plane stress/strain, 3 for solids.
int spatial_dimension(Formulation formulation);

class DofMap {
 public:
  DofMap() = default;
  /// Glues conforming interfaces: two sides (of different patches, or different sides of one
  /// patch) are glued when every control point of one coincides with a control point of the other
  /// in one of the grid orientations (reversal, transposition), to `relative_tolerance` times the
  /// model's bounding-box diagonal. Partially matching sides (T-junctions) are not glued. Sides
  /// of one patch are glued only when problem.glue_patch_seams is set (the default).
  DofMap(const Problem& problem, double relative_tolerance = 1e-6);

  int dofs_per_node() const { return dofs_per_node_; }
  int num_nodes() const { return num_nodes_; }
  int num_dofs() const { return num_nodes_ * dofs_per_node_; }
  int num_patches() const { return static_cast<int>(node_.size()); }
  int node(int patch, int control_point) const {
    return node_[static_cast<size_t>(patch)][static_cast<size_t>(control_point)];
  }
  int dof(int patch, int control_point, int component) const {
    return node(patch, control_point) * dofs_per_node_ + component;
  }
  /// Nodes of one patch, indexed by control point.
  const std::vector<int>& patch_nodes(int patch) const { return node_[static_cast<size_t>(patch)]; }
  /// Position of each node (its first control point).
  const std::vector<Eigen::Vector3d>& node_positions() const { return positions_; }
  /// Number of control-point pairs glued across interfaces.
  int glued_pairs() const { return glued_pairs_; }
  /// Two patch sides that lie on each other (same bounding box, area and centroid to 1e-6) but
  /// whose control points differ, so they were not glued: a non-conforming interface (different
  /// knots or degrees along it, e.g. after refining patches of different orientations
  /// differently). The model would fall apart there; check_rigid_body_modes refuses it.
  struct UngluedInterface {
    int patch_a, dir_a, end_a, patch_b, dir_b, end_b;
  };
  const std::vector<UngluedInterface>& unglued_interfaces() const { return unglued_; }

 private:
  int dofs_per_node_ = 3;
  int num_nodes_ = 0;
  int glued_pairs_ = 0;
  std::vector<UngluedInterface> unglued_;
  std::vector<std::vector<int>> node_;
  std::vector<Eigen::Vector3d> positions_;
};

}  // namespace isospring::analysis
