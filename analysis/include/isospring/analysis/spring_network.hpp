#pragma once
// A mass-spring network: the data a real-time engine needs. Built from a NURBS control net by the
// fitting module; its mechanics (forces, stiffness, integrators) live in the analysis module.
#include <Eigen/Core>
#include <array>
#include <vector>

namespace isospring::analysis {

struct Spring {
  int i = 0;  // particle indices, i < j
  int j = 0;
  double stiffness = 0.0;    // k [N/m]
  double damping = 0.0;      // c [N s/m], along the spring
  double rest_length = 0.0;  // L0 [m]
  int group = -1;            // calibration group (rest-length group), -1 when ungrouped
};

/// A volume (2D: area) term of one control-net cell: energy
///   E = 1/2 (modulus / |V0|) (V(x) - V0)^2,
/// V(x) the volume of the trilinear (2D: bilinear) cell through its corners, V0 its rest value.
/// Linearised at rest it adds (modulus / |V0|) b b^T with b = dV/dx (a rank-one block over the
/// corners), which stiffens volume change only: it is the bulk term central springs lack (a cubic
/// lattice of central springs has C12 = C44, i.e. nu = 1/4 when isotropic [W05]; a modulus
/// kappa = C44 adds kappa to C11 and C12 and gives nu = 1/3). Rigid motions keep V, so the
/// term has the rigid-body null space. Force: -(modulus / |V0|) (V - V0) dV/dx, per cell.
///
/// The same cell data carries a second energy, `kind == CellEnergy::kShear`: the
/// deviatoric (shear) energy of the cell's mean deformation gradient,
///   E = modulus |V0| |dev G|^2,  G = 1/2 (F^T F - I),  F = (1/V0) sum_a x_a (dV0/dx_a)^T,
/// (F is the cell's volume average of dx/dX, exact for affine motions; G its Green strain, so
/// the term is invariant under rigid motions of any size). Linearised at rest it is mu |V0|
/// |dev eps|^2 with modulus = mu [Pa]: a cell with a volume term kappa = lambda + 2 mu / d and a
/// shear term mu reproduces an isotropic solid exactly under every uniform strain. It sees only
/// the cell's mean strain (rank 5 in 3D, 2 in 2D), so the springs keep the cell's other modes.
enum class CellEnergy { kVolume, kShear };

struct VolumeTerm {
  /// Corners in tensor order (corner a + 2b + 4c at parametric (a, b, c)); 2D uses the first 4.
  std::array<int, 8> particles{};
  CellEnergy kind = CellEnergy::kVolume;
  double modulus = 0.0;      // kappa or mu [Pa] (2D: [N/m], per unit thickness)
  double rest_volume = 0.0;  // V0 [m^3] (2D: area [m^2]), signed by the corners' orientation
  int group = -1;            // calibration group, -1 when ungrouped
  /// Non-empty: a STRAIN-POINT term (spring_strain_point.hpp) instead of a net cell:
  /// F = sum_a x_{points[a]} gradients[a]^T with gradients[a] = dR_a/dX, the NURBS basis
  /// gradients at one point of the patch (e.g. a Gauss point of a knot span), over the
  /// (p+1)^d control points supporting it; rest_volume is the point's share of the patch volume
  /// (quadrature weight times |det J|). kVolume stores 1/2 kappa V0 (det F - 1)^2, kShear
  /// mu V0 |dev G|^2 as for a cell. `particles` is unused then.
  std::vector<int> points;
  std::vector<Eigen::Vector3d> gradients;
};

struct SpringNetwork {
  std::vector<Eigen::Vector3d> positions;  // rest positions [m]
  std::vector<double> masses;              // [kg]
  std::vector<bool> fixed;                 // particle held in place
  std::vector<Spring> springs;
  std::vector<VolumeTerm> volumes;  // usually empty: plain central springs
  int dimension = 3;                // 2 for in-plane models (z ignored)
};

}  // namespace isospring::analysis
