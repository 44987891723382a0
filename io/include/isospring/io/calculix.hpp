#pragma once
// CalculiX (ccx) input decks for a case and the displacements ccx prints to its .dat file.
//
// The deck solves the same problem as the IGA analysis with 20-node serendipity hexahedra (3D) or
// 8-node serendipity quadrilaterals (plane stress CPS8, plane strain CPE8, with the case's
// thickness): each knot span of each (discretised) patch becomes one element whose corner and
// mid-edge nodes are points of the exact NURBS geometry, so "matched refinement" means the same
// element grid.
// Loads become consistent nodal forces (tractions, pressures: quadrature of the face shape
// functions over the quadratic face) or *DLOAD (body force, gravity); supports become *BOUNDARY
// on the nodes of the supported sides. Each load case is one *STEP that replaces the loads of the
// previous one (OP=NEW) and prints U for every node.
#include <Eigen/Core>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "isospring/analysis/problem.hpp"

namespace isospring::io {

struct CalculixOptions {
  /// 3D: C3D20R (reduced 2x2x2 integration; CalculiX's recommended structural hexahedron: free
  /// of the shear and volumetric locking of full integration in bending) or C3D20 (full 3x3x3).
  /// Plane stress: CPS8R or CPS8; plane strain: CPE8R or CPE8. Empty: the reduced type.
  std::string element_type;
  /// Young's modulus of each element from its centroid (the mean of its corner nodes), for
  /// materials that vary in space (graded specimens, soft layers); empty: the case's E.
  std::function<double(const Eigen::Vector3d&)> youngs_modulus_at;
  /// Geometrically nonlinear steps (*STEP, NLGEOM): large displacements and rotations.
  bool nonlinear = false;
  /// The material as *HYPERELASTIC, NEO HOOKE (W = C10 (I1bar - 3) + (J - 1)^2 / D1 with
  /// C10 = mu / 2, D1 = 2 / K of E and nu: analysis/neo_hookean.hpp's law) instead of *ELASTIC.
  /// Needs `nonlinear` for large strains; plane stress is refused (as in the analysis).
  bool neo_hookean = false;
  /// Also print the reaction forces (*NODE PRINT RF) of every node in each step.
  bool print_reactions = false;
  /// When positive, ccx's Newton criteria (*CONTROLS, PARAMETERS=FIELD): residual force at most
  /// this fraction of the mean force, correction at most 100 times it of the increment. ccx's
  /// defaults (0.005 and 0.01) stop NLGEOM steps with relative errors of ~1e-5 and more; 1e-9
  /// converges to round-off in one or two more iterations. 0: ccx's defaults.
  double newton_tolerance = 0.0;
  /// Gauss points per direction for the consistent face loads (4 integrates curved faces and
  /// smooth traction functions well; flat faces with constant tractions are exact from 2).
  int face_quadrature = 4;
  std::string title = "isospring";
};

struct CalculixDeck {
  std::string text;                    // the .inp file
  std::vector<Eigen::Vector3d> nodes;  // node n (1-based in the deck) is nodes[n - 1]
  int elements = 0;
  std::string element_type;                // as written in *ELEMENT
  std::vector<std::string> load_case_ids;  // step s is load case load_case_ids[s - 1]
};

/// The deck for a problem. Throws nurbs::InputError for what a deck cannot express: supports or
/// loads on single control points, symmetry on a side whose normal is not a coordinate axis, an
/// element type that does not fit the formulation.
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

/// Every "forces (fx,fy,fz)" block (the reactions of CalculixOptions::print_reactions), in file
/// order, in the same form. Throws InputError naming the file when there is none.
std::vector<CalculixDisplacements> read_calculix_reactions(const std::filesystem::path& path);

}  // namespace isospring::io
