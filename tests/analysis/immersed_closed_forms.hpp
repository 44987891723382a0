#pragma once
// Closed-form solutions and error norms of the immersed elasticity tests.
#include <Eigen/Core>
#include <cmath>
#include <functional>

#include "isospring/analysis/elasticity.hpp"
#include "isospring/analysis/immersed.hpp"
#include "isospring/geometry/immersed_implicit.hpp"

namespace isospring::analysis::testing {

/// Kirsch: infinite plane-stress plate with a hole of radius a under far-field tension T along
/// x (the formulas of test_kirsch.cpp for a = 1, scaled: u(x; a) = a u(x / a; 1)).
struct Kirsch {
  double a = 1, T = 10, E = 1e5, nu = 0.3;
  Eigen::Matrix3d stress(const Eigen::Vector3d& x) const {
    const double r = x.head<2>().norm() / a, t = std::atan2(x.y(), x.x());
    const double a2 = 1.0 / (r * r), a4 = a2 * a2;
    Eigen::Matrix3d s = Eigen::Matrix3d::Zero();
    s(0, 0) = T * (1 - a2 * (1.5 * std::cos(2 * t) + std::cos(4 * t)) + 1.5 * a4 * std::cos(4 * t));
    s(1, 1) = T * (-a2 * (0.5 * std::cos(2 * t) - std::cos(4 * t)) - 1.5 * a4 * std::cos(4 * t));
    s(0, 1) = s(1, 0) =
        T * (-a2 * (0.5 * std::sin(2 * t) + std::sin(4 * t)) + 1.5 * a4 * std::sin(4 * t));
    return s;
  }
  Eigen::Vector3d displacement(const Eigen::Vector3d& x) const {
    const double r = x.head<2>().norm() / a, t = std::atan2(x.y(), x.x());
    const double mu = E / (2 * (1 + nu)), kappa = (3 - nu) / (1 + nu), c = a * T / (8 * mu);
    return {
        c * (r * (kappa + 1) * std::cos(t) + 2 / r * ((1 + kappa) * std::cos(t) + std::cos(3 * t)) -
             2 / (r * r * r) * std::cos(3 * t)),
        c * (r * (kappa - 3) * std::sin(t) + 2 / r * ((1 - kappa) * std::sin(t) + std::sin(3 * t)) -
             2 / (r * r * r) * std::sin(3 * t)),
        0.0};
  }
};

/// Lame thick cylinder Ri..Ro under internal pressure P, plane strain.
struct LameCylinder {
  double ri = 1, ro = 2, E = 1e5, nu = 0.3, P = 10;
  double radial(double r) const {
    const double e = E / (1 - nu * nu), n = nu / (1 - nu);
    return P * ri * ri / (e * (ro * ro - ri * ri)) * ((1 - n) * r + (1 + n) * ro * ro / r);
  }
  Eigen::Vector3d displacement(const Eigen::Vector3d& x) const {
    const double r = x.head<2>().norm();
    return Eigen::Vector3d(x.x(), x.y(), 0.0) * (radial(r) / r);
  }
  Eigen::Matrix3d stress(const Eigen::Vector3d& x) const {
    const double r2 = x.head<2>().squaredNorm(), c = P * ri * ri / (ro * ro - ri * ri);
    const double srr = c * (1 - ro * ro / r2), stt = c * (1 + ro * ro / r2);
    const double t = std::atan2(x.y(), x.x()), cs = std::cos(t), sn = std::sin(t);
    Eigen::Matrix3d s = Eigen::Matrix3d::Zero();
    s(0, 0) = srr * cs * cs + stt * sn * sn;
    s(1, 1) = srr * sn * sn + stt * cs * cs;
    s(0, 1) = s(1, 0) = (srr - stt) * sn * cs;
    s(2, 2) = nu * (srr + stt);
    return s;
  }
};

struct ErrorNorms {
  double l2 = 0;                          // ||u - u_h||_L2
  double h1 = 0;                          // |u - u_h|_H1 (full gradient), when a gradient is given
  double energy = 0;                      // sqrt(int (sigma - sigma_h) : (eps - eps_h))
  double l2_exact = 0, energy_exact = 0;  // the same norms of the exact solution
};

/// Errors over `quadrature`'s cells (a domain on the same grid, usually with more points).
inline ErrorNorms immersed_errors(
    const geometry::ImmersedDomain& domain, const ImmersedResult& result,
    const ImmersedOptions& options, const geometry::ImmersedDomain& quadrature,
    const std::function<Eigen::Vector3d(const Eigen::Vector3d&)>& u,
    const std::function<Eigen::Matrix3d(const Eigen::Vector3d&)>& sigma,
    const std::function<Eigen::Matrix3d(const Eigen::Vector3d&)>& gradient = {}) {
  ErrorNorms e;
  for (const auto& cell : quadrature.cells)
    for (size_t q = 0; q < cell.points.size(); ++q) {
      const Eigen::Vector3d& x = cell.points[q];
      const double w = cell.weights[q];
      const ImmersedPointValue v = evaluate_immersed(domain, result, x);
      const Eigen::Vector3d ue = u(x);
      e.l2 += w * (ue - v.displacement).squaredNorm();
      e.l2_exact += w * ue.squaredNorm();
      const Eigen::Matrix3d se = sigma(x);
      const Eigen::Matrix3d sh = immersed_stress(domain, result, options, x);
      const Eigen::Matrix3d ee = strain_from_stress(se, options.material, options.formulation);
      const Eigen::Matrix3d eh = strain_from_stress(sh, options.material, options.formulation);
      e.energy += w * (se - sh).cwiseProduct(ee - eh).sum();
      e.energy_exact += w * se.cwiseProduct(ee).sum();
      if (gradient) e.h1 += w * (gradient(x) - v.gradient).squaredNorm();
    }
  e.l2 = std::sqrt(e.l2);
  e.h1 = std::sqrt(e.h1);
  e.energy = std::sqrt(e.energy);
  e.l2_exact = std::sqrt(e.l2_exact);
  e.energy_exact = std::sqrt(e.energy_exact);
  return e;
}

}  // namespace isospring::analysis::testing
