#pragma once
// Quadrature of a box intersected with a solid, along lines intersected exactly with its B-rep
// (see immersed_cad.hpp for the method and why).
#include <Eigen/Core>
#include <vector>

#include "immersed_cad_lines.hpp"
#include "isospring/geometry/immersed_domain.hpp"

namespace isospring::geometry::detail {

struct CutCellSettings {
  int order = 4;            // Gauss points per direction and piece
  double tolerance = 1e-7;  // accepted |V(order) - V(order + 2)| / volume of the background cell
  int max_depth = 4;        // bisections of a box that does not reach the tolerance
};

struct CutCellRule {
  std::vector<Eigen::Vector3d> points;
  std::vector<double> weights;
  bool crossed = false;  // a line met the boundary inside the box
  bool inside = false;   // not crossed: its lines are wholly inside the part (else outside)
};

struct CutCellStats {
  long boxes = 0;                 // boxes integrated (cells and their children)
  int unresolved = 0;             // leaves at max_depth above the tolerance
  double unresolved_error = 0.0;  // their summed |V(order) - V(order + 2)| (m^3)
};

/// The rule of [lo, hi] intersected with the solid. `boundary` holds the boundary points inside
/// the box (their normals choose the line direction). A box is accepted when its volumes with
/// the two orders differ by less than tolerance x `cell_volume` (the background cell's): a box
/// holding a singular point (a tangency, an edge crossing obliquely) has the same relative error
/// at any size, so only its absolute error shrinks, by 8 per bisection.
CutCellRule cut_cell_rule(SolidProbe& probe, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                          const std::vector<const BoundaryPoint*>& boundary,
                          const CutCellSettings& settings, double cell_volume, CutCellStats& stats,
                          int depth = 0);

}  // namespace isospring::geometry::detail
