#pragma once
// Models shared by the finite-strain material tests (SVK and neo-Hookean): curved rational
// patches in 2D and 3D for tangent and rotation checks, random displacement fields, and a slender
// plane-strain cantilever under an end shear traction.
#include <Eigen/Core>
#include <random>

#include "analysis_models.hpp"
#include "isospring/analysis/problem.hpp"

namespace isospring::analysis::finite_strain_models {

inline Problem curved_2d() {
  Problem problem;
  problem.formulation = Formulation::kPlaneStrain;
  problem.material = {200.0, 0.3, 1.0, 1.0};
  problem.patches.push_back(nurbs::refine_uniform(isospring::testing::kirsch_plate(), 1, 2));
  return problem;
}

inline Problem curved_3d() {
  Problem problem;
  problem.formulation = Formulation::kSolid;
  problem.material = {200.0, 0.3, 1.0, 1.0};
  problem.patches.push_back(isospring::testing::sphere_octant(1.0, 1.5));
  return problem;
}

// Displacement with every component random of size `scale` (a deformation of tens of percent
// strain for scale 0.1 on these unit-size models).
inline Eigen::VectorXd random_field(int size, double scale, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-scale, scale);
  Eigen::VectorXd u(size);
  for (Eigen::Index i = 0; i < size; ++i) u[i] = uniform(rng);
  return u;
}

// Slender plane-strain cantilever, clamped at x = 0, uniform shear traction q on the free end.
inline Problem cantilever(double q) {
  Problem problem;
  problem.formulation = Formulation::kPlaneStrain;
  problem.material = {1000.0, 0.3, 1.0, 1.0};
  problem.patches.push_back(isospring::testing::beam(10.0, 1.0, 2, 10, 2));
  Support clamp;
  clamp.side = {0, 0, 0};
  clamp.fixed = {true, true, false};
  problem.supports.push_back(clamp);
  LoadCase load;
  load.id = "tip";
  Traction t;
  t.side = {0, 0, 1};
  t.value = {0.0, -q, 0.0};
  load.tractions.push_back(t);
  problem.load_cases.push_back(load);
  return problem;
}

}  // namespace isospring::analysis::finite_strain_models
