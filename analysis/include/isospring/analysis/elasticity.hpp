#pragma once
// Isotropic linear elasticity for plane stress, plane strain and 3D solids.
#include <Eigen/Core>

#include "isospring/analysis/problem.hpp"

namespace isospring::analysis {

/// Lame parameters of the formulation: plane stress uses the reduced lambda* = 2 lambda mu /
/// (lambda + 2 mu), so that every formulation reads sigma = lambda tr(eps) I + 2 mu eps in its
/// own dimension.
struct LameParameters {
  double lambda = 0.0;
  double mu = 0.0;
};
LameParameters lame_parameters(const Material& material, Formulation formulation);

/// Out-of-plane thickness factor of integrals: the material thickness in 2D, 1 for solids.
double thickness_factor(const Problem& problem);

/// Full 3x3 stress from the (in-plane for 2D) symmetric strain: szz = nu (sxx + syy) for plane
/// strain, 0 for plane stress.
Eigen::Matrix3d stress_from_strain(const Eigen::Matrix3d& strain, const Material& material,
                                   Formulation formulation);
/// Strain energy density-conjugate strain of a stress: in 2D only the in-plane components of
/// `stress` are used (plane strain eliminates szz through ezz = 0); ezz is returned for plane
/// stress.
Eigen::Matrix3d strain_from_stress(const Eigen::Matrix3d& stress, const Material& material,
                                   Formulation formulation);
/// von Mises equivalent stress of a full 3x3 stress.
double von_mises(const Eigen::Matrix3d& stress);

/// Throws nurbs::InputError unless E > 0 and -1 < nu < 0.5 (and thickness > 0 in 2D).
void check_material(const Material& material, Formulation formulation);

}  // namespace isospring::analysis
