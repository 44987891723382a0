#pragma once
// Strain-point terms of a spring network: the volume and shear energies of a
// VolumeTerm evaluated on the deformation gradient of the NURBS displacement field at one point
// of a patch instead of on a control-net cell's mean strain.
//
// Why: a net cell's terms couple only its 4 (8) corners and see only the cell's mean strain,
// and a corner particle of a membrane carries 3 cell springs: neither represents the degree-2
// IGA stiffness, which couples every control point with those up to two net steps away through
// the basis gradients dR_a/dX. A strain point stores F = sum_a x_a (dR_a/dX)^T over the
// (p+1)^d control points supporting it, exact for every affine motion (partition of unity), and
//   E = 1/2 kappa V0 (det F - 1)^2    (CellEnergy::kVolume)
//   E = mu V0 |dev G|^2, G = 1/2 (F^T F - I)    (CellEnergy::kShear),
// both invariant under rigid motions of any size. Linearised at rest the pair is
// V0 (mu |dev eps|^2 + kappa/2 (tr eps)^2) at that point: with the Gauss points of the
// analysis (degree + 1 per direction), their weights and the material's moduli the spring
// model's stiffness IS the IGA stiffness (SpringStrainPoint.GaussPointsReproduceTheIgaStiffness);
// with fewer points (1 per knot span: reduced integration) the calibration fits a modulus per
// point and the springs carry the modes the points miss.
#include <Eigen/Core>
#include <vector>

#include "isospring/analysis/spring_network.hpp"
#include "isospring/nurbs/patch.hpp"

namespace isospring::analysis {

/// One point of a patch: the control points (patch indices) whose basis is non-zero there,
/// their gradients dR_a/dX (the unused components zero in 2D), and its volume share.
struct StrainPointSite {
  std::vector<int> control_points;
  std::vector<Eigen::Vector3d> gradients;
  double volume = 0.0;  // Gauss weight times |det dX/dxi| [m^3] (2D: [m^2])
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
};

/// `points_per_direction` Gauss points per direction in every knot span of `patch` (a surface in
/// the plane or a volume). Points where det dX/dxi is not positive beyond round-off (collapsed
/// corners meet them only on the boundary, never at a Gauss point) are skipped.
std::vector<StrainPointSite> strain_point_sites(const nurbs::Patch& patch,
                                                int points_per_direction);

/// V0 det F(x) of a strain-point term (the volume kind's V(x)) with its gradient and Hessian over
/// the term's points (point-major, `dimension` components each) when not null.
double strain_point_volume(const VolumeTerm& term, const Eigen::VectorXd& x, int dimension,
                           Eigen::VectorXd* gradient = nullptr, Eigen::MatrixXd* hessian = nullptr);

/// mu V0 |dev G|^2 of a strain-point term at x, gradient and Hessian like strain_point_volume.
double strain_point_shear_energy(const VolumeTerm& term, const Eigen::VectorXd& x, int dimension,
                                 Eigen::VectorXd* gradient = nullptr,
                                 Eigen::MatrixXd* hessian = nullptr);

/// The term's rest volume gradient b_a = V0 dR_a/dX (point-major), dV/dx at rest.
Eigen::VectorXd strain_point_rest_gradient(const VolumeTerm& term, int dimension);

}  // namespace isospring::analysis
