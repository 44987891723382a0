#pragma once
// The springs and cell terms of one control net, seen through its particles. Shared by the
// body-fitted spring mesh (every control point of a patch is a particle) and the immersed one
// (only the background grid's active control points are), so both build the same topology.
#include <Eigen/Core>
#include <array>
#include <functional>
#include <set>
#include <utility>
#include <vector>

#include "isospring/analysis/spring_network.hpp"
#include "isospring/fitting/spring_mesh.hpp"

namespace isospring::fitting::detail {

/// A control net of n[0] x n[1] x n[2] points (1 beyond its dimension); particle(i, j, k) is the
/// particle carrying point (i, j, k), or -1 when the point carries none (an inactive control
/// point of an immersed background grid).
struct NetView {
  std::array<int, 3> n{1, 1, 1};
  std::function<int(int, int, int)> particle;
};

/// Every pair of points of every block of (r + 1) points per direction, r = 1 .. reach (smaller
/// where the net is), whose points all carry particles, as (smaller, larger) particle pairs in
/// `pairs`. A block with a point without a particle is left out whole, so an immersed net gets
/// the springs of its complete cells only, as a body-fitted net of the same points would. Pairs
/// closer than `tolerance` (collapsed cells) are counted in `collapsed` instead.
void collect_block_pairs(const NetView& net, int reach,
                         const std::vector<Eigen::Vector3d>& positions, double tolerance,
                         std::set<std::pair<int, int>>& pairs, int& collapsed);

/// One spring per pair, rest length from the network's positions, in the pairs' order.
void add_springs(const std::set<std::pair<int, int>>& pairs, analysis::SpringNetwork& network);

/// One cell term of `kind` per net cell whose corners all carry particles (corners in tensor
/// order); cells with |volume| <= min_volume are skipped and counted. Returns that count.
int add_net_cell_terms(const NetView& net, analysis::CellEnergy kind, double min_volume,
                       analysis::SpringNetwork& network);

/// The warning of `count` cells skipped by add_net_cell_terms ("" when none).
std::string skipped_cells_warning(int count, analysis::CellEnergy kind);

/// The diagonal of the points' bounding box (0 for none).
double bounding_box_diagonal(const std::vector<Eigen::Vector3d>& points);

}  // namespace isospring::fitting::detail
