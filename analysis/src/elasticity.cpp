// Isotropic constitutive law.
#include "isospring/analysis/elasticity.hpp"

#include <cmath>

#include "isospring/nurbs/error.hpp"

namespace isospring::analysis {

LameParameters lame_parameters(const Material& m, Formulation formulation) {
  const double E = m.youngs_modulus, nu = m.poisson_ratio;
  LameParameters lame;
  lame.mu = E / (2.0 * (1.0 + nu));
  lame.lambda = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
  if (formulation == Formulation::kPlaneStress)
    lame.lambda = 2.0 * lame.lambda * lame.mu / (lame.lambda + 2.0 * lame.mu);
  return lame;
}

double thickness_factor(const Problem& problem) {
  return problem.formulation == Formulation::kSolid ? 1.0 : problem.material.thickness;
}

Eigen::Matrix3d stress_from_strain(const Eigen::Matrix3d& strain, const Material& material,
                                   Formulation formulation) {
  const LameParameters lame = lame_parameters(material, formulation);
  Eigen::Matrix3d stress = Eigen::Matrix3d::Zero();
  if (formulation == Formulation::kSolid) {
    stress = lame.lambda * strain.trace() * Eigen::Matrix3d::Identity() + 2.0 * lame.mu * strain;
    return stress;
  }
  const Eigen::Matrix2d e = strain.topLeftCorner<2, 2>();
  stress.topLeftCorner<2, 2>() =
      lame.lambda * e.trace() * Eigen::Matrix2d::Identity() + 2.0 * lame.mu * e;
  if (formulation == Formulation::kPlaneStrain)
    stress(2, 2) = material.poisson_ratio * (stress(0, 0) + stress(1, 1));
  return stress;
}

Eigen::Matrix3d strain_from_stress(const Eigen::Matrix3d& stress, const Material& material,
                                   Formulation formulation) {
  const double E = material.youngs_modulus, nu = material.poisson_ratio;
  Eigen::Matrix3d s = stress;
  if (formulation != Formulation::kSolid) {
    // Only the in-plane stress is independent: szz is 0 (plane stress) or follows from ezz = 0.
    s.row(2).setZero();
    s.col(2).setZero();
    if (formulation == Formulation::kPlaneStrain) s(2, 2) = nu * (s(0, 0) + s(1, 1));
  }
  Eigen::Matrix3d strain = ((1.0 + nu) * s - nu * s.trace() * Eigen::Matrix3d::Identity()) / E;
  if (formulation == Formulation::kPlaneStrain) strain(2, 2) = 0.0;
  return strain;
}

double von_mises(const Eigen::Matrix3d& s) {
  const double a = s(0, 0) - s(1, 1), b = s(1, 1) - s(2, 2), c = s(2, 2) - s(0, 0);
  return std::sqrt(0.5 * (a * a + b * b + c * c) +
                   3.0 * (s(0, 1) * s(0, 1) + s(1, 2) * s(1, 2) + s(0, 2) * s(0, 2)));
}

void check_material(const Material& m, Formulation formulation) {
  if (!(m.youngs_modulus > 0.0) || !std::isfinite(m.youngs_modulus))
    throw nurbs::InputError("material.youngs_modulus is " + std::to_string(m.youngs_modulus) +
                            ": Young's modulus must be a positive finite number [Pa]");
  if (!(m.poisson_ratio > -1.0 && m.poisson_ratio < 0.5))
    throw nurbs::InputError("material.poisson_ratio is " + std::to_string(m.poisson_ratio) +
                            ": Poisson's ratio must lie strictly between -1 and 0.5");
  if (formulation != Formulation::kSolid && !(m.thickness > 0.0 && std::isfinite(m.thickness)))
    throw nurbs::InputError("material.thickness is " + std::to_string(m.thickness) +
                            ": a plane stress/strain model needs a positive thickness [m]");
  if (!(m.density >= 0.0) || !std::isfinite(m.density))
    throw nurbs::InputError("material.density is " + std::to_string(m.density) +
                            ": the density must be zero or positive [kg/m^3]");
}

}  // namespace isospring::analysis
