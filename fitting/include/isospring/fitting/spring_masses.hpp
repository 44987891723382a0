#pragma once
// Particle masses and per-spring stiffness bounds of an NMSM.
#include <vector>

#include "isospring/analysis/problem.hpp"
#include "isospring/fitting/spring_mesh.hpp"

namespace isospring::fitting {

enum class MassModel {
  kLumpedIga,  // row-sum lumped IGA mass [NC10 (2)]: positive, sums to rho * volume exactly
  kNetCells,   // [S15 3.12]: each control-net cell's rho * volume shared equally by its corners
};

/// A cell of a control net: its corner particles (4 or 8, may repeat in collapsed cells) and its
/// area (times the thickness in 2D) or volume measured on the control net.
struct NetCell {
  std::vector<int> corners;
  double measure = 0.0;
};

/// Cells of every patch's control net, with the mesh's particle numbering. Quadrilateral areas
/// from the cross product of the diagonals; hexahedra as 6 tetrahedra around the main diagonal
/// (exact for planar faces).
std::vector<NetCell> net_cells(const analysis::Problem& problem, const SpringMesh& mesh);

/// Sets mesh.network.masses. Throws nurbs::InputError unless the density is positive.
void assign_masses(const analysis::Problem& problem, SpringMesh& mesh, MassModel model);

/// [S15 4.19, 5.8] upper bound of each spring: sum over cells e containing particle i of
/// sqrt(d) E (1 + nu) max_e(Vol) / (2 L0^2), d the spatial dimension.
std::vector<double> stiffness_upper_bounds(const analysis::Problem& problem,
                                           const SpringMesh& mesh);

}  // namespace isospring::fitting
