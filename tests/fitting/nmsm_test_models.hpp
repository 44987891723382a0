#pragma once
// Small NURBS models for the NMSM tests: rectangular/box control nets on uniform knot vectors.
#include <algorithm>
#include <vector>

#include "isospring/analysis/problem.hpp"
#include "isospring/nurbs/patch.hpp"

namespace isospring::fitting::testing {

/// A patch with n[d] control points per direction on a regular grid of [0, size[d]] (degree
/// min(2, n - 1)); n.size() is the parametric dimension. A uniform B-spline with a regular
/// (Greville-spaced would be exact linear) grid of control points is a valid, slightly
/// non-uniformly parametrised block.
inline nurbs::Patch grid_patch(const std::vector<int>& n, const std::vector<double>& size) {
  std::vector<nurbs::KnotVector> knots;
  for (int count : n) {
    const int degree = std::min(2, count - 1);
    knots.push_back(nurbs::KnotVector::uniform(degree, count - degree));
  }
  const int n2 = n.size() == 3 ? n[2] : 1;
  std::vector<Eigen::Vector3d> points;
  for (int k = 0; k < n2; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i)
        points.emplace_back(size[0] * i / (n[0] - 1), size[1] * j / (n[1] - 1),
                            n2 > 1 ? size[2] * k / (n2 - 1) : 0.0);
  return nurbs::Patch(knots, points);
}

/// Problem on one grid patch: side u0 fixed, material E = 15 kPa, nu = 1/3, rho = 1143.
inline analysis::Problem grid_problem(const std::vector<int>& n, const std::vector<double>& size) {
  analysis::Problem problem;
  problem.patches.push_back(grid_patch(n, size));
  problem.formulation =
      n.size() == 3 ? analysis::Formulation::kSolid : analysis::Formulation::kPlaneStrain;
  problem.material.youngs_modulus = 15000.0;
  problem.material.poisson_ratio = 1.0 / 3.0;
  problem.material.density = 1143.0;
  analysis::Support support;
  support.side = analysis::Side{0, 0, 0};
  support.fixed = {true, true, n.size() == 3};
  problem.supports.push_back(support);
  return problem;
}

}  // namespace isospring::fitting::testing
