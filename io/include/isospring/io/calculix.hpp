#pragma once
// CalculiX (ccx) input decks for a 3D case and the displacements ccx prints to its .dat file.
//
// The deck solves the same problem as the IGA analysis with 20-node serendipity hexahedra: each
// knot span of each (discretised) patch becomes one element whose corner and mid-edge nodes are
// points of the exact NURBS geometry, so "matched refinement" means the same element grid.
// Loads become consistent nodal forces (tractions, pressures: quadrature of the face shape
// functions over the quadratic face) or *DLOAD (body force, gravity); supports become *BOUNDARY
// on the nodes of the supported sides. Each load case is one *STEP that replaces the loads of the
// previous one (OP=NEW) and prints U for every node.
#include <Eigen/Core>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "isospring/analysis/problem.hpp"

namespace isospring::io {

struct CalculixOptions {
  /// C3D20R (reduced 2x2x2 integration; CalculiX's recommended structural hexahedron: free of
  /// the shear and volumetric locking of full integration in bending) or C3D20 (full 3x3x3).
  std::string element_type = "C3D20R";
  /// Gauss points per direction for the consistent face loads (4 integrates curved faces and
  /// smooth traction functions well; flat faces with constant tractions are exact from 2).
  int face_quadrature = 4;
  std::string title = "isospring";
};

struct CalculixDeck {
  std::string text;                    // the .inp file
  std::vector<Eigen::Vector3d> nodes;  // node n (1-based in the deck) is nodes[n - 1]
  int elements = 0;
  std::vector<std::string> load_case_ids;  // step s is load case load_case_ids[s - 1]
};

/// The deck for a solid (3D) problem. Throws nurbs::InputError for what a deck cannot express:
/// 2D problems, supports or loads on single control points, symmetry on a side whose normal is
/// not a coordinate axis.
CalculixDeck make_calculix_deck(const analysis::Problem& problem,
                                const CalculixOptions& options = {});

/// Displacements of one *NODE PRINT block: node number -> (ux, uy, uz).
struct CalculixDisplacements {
  double time = 0.0;  // step time at which ccx printed them (1, 2, ... for consecutive steps)
  std::map<int, Eigen::Vector3d> nodes;
};

/// Every "displacements (vx,vy,vz)" block of a ccx .dat file, in file order. Throws InputError
/// naming the file when it is missing or has no displacement block.
std::vector<CalculixDisplacements> read_calculix_dat(const std::filesystem::path& path);

}  // namespace isospring::io
