#pragma once
// The serendipity mesh a CalculiX deck is written on (make_calculix_deck): one element per knot
// span of every patch, its nodes exact NURBS points at element corners and mid-edges, coincident
// nodes of different patches merged. Private to io; shared by the deck writer and its
// consistent side loads (calculix_side_loads.cpp).
#include <Eigen/Core>
#include <array>
#include <map>
#include <vector>

#include "isospring/analysis/problem.hpp"
#include "isospring/nurbs/quadrature.hpp"

namespace isospring::io::calculix_detail {

/// Corner and mid-edge nodes of one patch on its "fine" parametric grid: knot values and span
/// midpoints, (2 n_d + 1) per direction. A fine-grid point is a node when at most one of its
/// indices is odd (face and body centres are not nodes of a serendipity element).
struct PatchNodes {
  std::array<int, 3> size{};  // fine-grid points per direction
  std::array<std::vector<double>, 3> params;
  std::vector<int> node;  // fine-grid index -> global node (0-based), -1 when none
  bool flip = false;      // left-handed parametrisation: reverse w in the elements
  int at(int a, int b, int c) const {
    return node[static_cast<size_t>(a + size[0] * (b + size[1] * c))];
  }
};

/// Every patch's nodes (in the order of problem.patches) and the merged node positions.
struct DeckMesh {
  std::vector<PatchNodes> patches;
  std::vector<Eigen::Vector3d> nodes;  // global node n (0-based)
};

/// The mesh of every patch of `problem`; throws nurbs::InputError when a patch's parametric
/// dimension is not `dim` (2 for plane cases, 3 for solids).
DeckMesh mesh_patches(const analysis::Problem& problem, int dim);

/// Face nodes in (s, t) fine offsets: corners, then mid-edges (8-node serendipity quad).
inline constexpr int kQuad8[8][2] = {{0, 0}, {2, 0}, {2, 2}, {0, 2},
                                     {1, 0}, {2, 1}, {1, 2}, {0, 1}};

/// Fine-grid index of a side point: `dir` fixed at the side, (s, t) along the other two.
std::array<int, 3> side_index(const PatchNodes& pn, int dir, int end, int s, int t);

/// Consistent nodal forces of a load case's tractions and pressures, f_a = integral of N_a t dA
/// over each element face (3-node edges times the thickness in 2D), with `rule` per direction;
/// global node (0-based) -> force.
std::map<int, Eigen::Vector3d> side_load_forces(const analysis::Problem& problem,
                                                const DeckMesh& mesh, const nurbs::GaussRule& rule,
                                                const analysis::LoadCase& lc);

}  // namespace isospring::io::calculix_detail
