#pragma once
// Thick-walled cylinder under internal pressure (Lame), plane strain: the closed form and the
// exact quarter-ring model, shared by the displacement and B-bar verification tests.
#include <cmath>

#include "analysis_models.hpp"
#include "isospring/analysis/problem.hpp"
#include "isospring/nurbs/refine.hpp"

namespace isospring::testing {

constexpr double kLameRi = 1.0, kLameRo = 2.0;

struct LameCylinder {
  double E, nu, P;
  // Plane strain = the plane-stress formula with E' = E / (1 - nu^2), nu' = nu / (1 - nu).
  double radial(double r) const {
    const double e = E / (1 - nu * nu), n = nu / (1 - nu);
    return P * kLameRi * kLameRi / (e * (kLameRo * kLameRo - kLameRi * kLameRi)) *
           ((1 - n) * r + (1 + n) * kLameRo * kLameRo / r);
  }
  Eigen::Vector3d displacement(const Eigen::Vector3d& x) const {
    const double r = x.head<2>().norm();
    return Eigen::Vector3d(x.x(), x.y(), 0.0) * (radial(r) / r);
  }
  Eigen::Matrix3d stress(const Eigen::Vector3d& x) const {
    const double r = x.head<2>().norm(),
                 c = P * kLameRi * kLameRi / (kLameRo * kLameRo - kLameRi * kLameRi);
    const double srr = c * (1 - kLameRo * kLameRo / (r * r)),
                 stt = c * (1 + kLameRo * kLameRo / (r * r));
    return polar_to_cartesian(srr, stt, nu * (srr + stt), std::atan2(x.y(), x.x()));
  }
};

/// Quarter cylinder with symmetry supports and the internal pressure.
inline analysis::Problem lame_cylinder(const LameCylinder& lame, const nurbs::Patch& patch) {
  using namespace analysis;
  Problem problem;
  problem.formulation = Formulation::kPlaneStrain;
  problem.material = {lame.E, lame.nu, 1.0, 1.0};
  problem.patches.push_back(patch);
  for (int end = 0; end < 2; ++end) {
    Support symmetry;
    symmetry.side = {0, 1, end};  // v0: y = 0, v1: x = 0
    symmetry.symmetry = true;
    problem.supports.push_back(symmetry);
  }
  LoadCase load;
  load.id = "internal pressure";
  load.pressures.push_back({{0, 0, 0}, lame.P});
  problem.load_cases.push_back(load);
  return problem;
}

/// Degree p in both directions (C^{p-1}), n x n elements.
inline nurbs::Patch lame_ring(int p, int n, double weight = kSqrtHalf) {
  return nurbs::k_refine(quarter_ring(kLameRi, kLameRo, weight), {p, p, 0}, {n, n, 1});
}

}  // namespace isospring::testing
