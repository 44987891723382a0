#pragma once
// The NMSM topology [S15 ch. 5]: every control point is a particle; springs on the control net.
//
// 2D nets: stretch springs on the net edges and shear springs on both diagonals of every cell.
// 3D nets: the 12 edges, both diagonals of the 6 faces and the 4 body diagonals of every cell.
// Cells share edges and faces, so springs are collected by particle pair: each spring exactly once.
#include <string>
#include <vector>

#include "isospring/analysis/problem.hpp"
#include "isospring/analysis/spring_network.hpp"

namespace isospring::fitting {

struct SpringMeshOptions {
  /// Merge coincident control points of the model into one particle (seams of closed patches,
  /// the collapsed points of a single-patch disk). Off: only the analysis' interface gluing.
  bool merge_coincident = false;
  /// Two points coincide when closer than this times the control-net bounding-box diagonal.
  double relative_tolerance = 1e-9;
  /// 1: [S15]'s topology, every pair of corners of a net cell. 2: every pair of points of every
  /// 3 x 3 (x 3) block of the net, i.e. also springs two net steps apart. A degree-2 IGA
  /// stiffness couples control points that far apart (basis supports overlap over 3 knot spans),
  /// which the cell springs cannot represent: with reach 2 the model is still plain central
  /// springs (exports and real-time solvers unchanged), ~3x (2D) to ~5x (3D) more of them.
  int reach = 1;
  /// Also one volume (2D: area) term per net cell (analysis::VolumeTerm, spring_volume.hpp):
  /// stiffness against volume change that central springs lack (their lattice has a fixed
  /// Poisson ratio). Cells of (near) zero volume (collapsed corners) get none. Off: plain springs.
  bool volume_terms = false;
  /// Also one shear term per net cell (analysis::CellEnergy::kShear): the deviatoric energy of
  /// the cell's mean strain, after the volume terms in SpringNetwork::volumes. With volume terms
  /// a cell holds a full isotropic small-strain energy (bulk and shear moduli fitted apart).
  bool shear_terms = false;
  /// > 0: also a volume and a shear strain-point term (analysis/spring_strain_point.hpp) at each
  /// of this many Gauss points per direction of every knot span, on the NURBS basis gradients of
  /// the control points supporting it (after the cell terms in SpringNetwork::volumes). 1 is the
  /// reduced rule (one point per span); degree + 1 with the material's moduli is the IGA
  /// stiffness itself. 0: none.
  int strain_points = 0;
};

/// A spring network on the control nets of a model plus the map back to control points.
struct SpringMesh {
  analysis::SpringNetwork network;  // stiffness 0, masses 0, nothing fixed: set by the caller
  /// particle[patch][control point]: the particle carrying that control point.
  std::vector<std::vector<int>> particle;
  /// Human-readable notes, e.g. "skipped 4 zero-length springs (collapsed net cells)".
  std::vector<std::string> warnings;
  int num_control_points() const;
};

/// Springs of the control nets of `problem.patches`. Control points glued by the analysis DofMap
/// (conforming interfaces) share a particle, so the NMSM and the IGA reference live on the same
/// nodes; the network's dimension is the problem's spatial dimension. Springs whose end points
/// coincide (degenerate cells) are skipped with a warning, since they have no direction.
/// Throws nurbs::InputError for curve patches (parametric dimension 1).
SpringMesh build_spring_mesh(const analysis::Problem& problem,
                             const SpringMeshOptions& options = {});

/// Number of springs of one n0 x n1 (x n2) net by the closed-form count (no merging, no gluing).
long expected_spring_count(int n0, int n1, int n2 = 1);

/// The nodes of the analysis DofMap as particles: node_of[patch][cp] and, for each node, its
/// particle (identity unless options.merge_coincident merged coincident nodes).
std::vector<int> particle_of_node(const analysis::Problem& problem, const SpringMesh& mesh);

}  // namespace isospring::fitting
