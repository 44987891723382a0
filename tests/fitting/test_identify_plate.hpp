#pragma once
// A small plane-stress plate for the identification tests: [0, 0.1] x [0, 0.04] m, degree 2,
// clamped on the left side (u0), two load cases on the right side (tension L1, shear L2), and a
// grid of markers in the plate.
#include <random>

#include "isospring/analysis/problem.hpp"
#include "isospring/fitting/measure.hpp"
#include "isospring/nurbs/knot_vector.hpp"

namespace isospring::fitting::testing {

inline nurbs::Patch rectangle(double length, double width, int nx, int ny, int degree = 2,
                              double x0 = 0.0) {
  const nurbs::KnotVector ku = nurbs::KnotVector::uniform(degree, nx);
  const nurbs::KnotVector kv = nurbs::KnotVector::uniform(degree, ny);
  // Greville abscissae make the parametrisation linear (uniform Jacobian).
  auto greville = [degree](const nurbs::KnotVector& k, int i) {
    double s = 0.0;
    for (int j = 1; j <= degree; ++j) s += k[i + j];
    return s / degree;
  };
  std::vector<Eigen::Vector3d> points;
  for (int j = 0; j < kv.num_basis(); ++j)
    for (int i = 0; i < ku.num_basis(); ++i)
      points.emplace_back(x0 + length * greville(ku, i), width * greville(kv, j), 0.0);
  return nurbs::Patch({ku, kv}, points);
}

inline analysis::Problem plate_problem(int nx = 8, int ny = 4) {
  analysis::Problem problem;
  problem.patches.push_back(rectangle(0.1, 0.04, nx, ny));
  problem.formulation = analysis::Formulation::kPlaneStress;
  problem.material.youngs_modulus = 1e6;
  problem.material.poisson_ratio = 0.3;
  problem.material.density = 100.0;
  problem.material.thickness = 0.005;
  analysis::Support clamp;
  clamp.side = analysis::parse_side("u0");
  clamp.fixed = {true, true, false};
  problem.supports.push_back(clamp);
  analysis::LoadCase tension;
  tension.id = "L1";
  tension.tractions.push_back({analysis::parse_side("u1"), Eigen::Vector3d(2000.0, 0, 0), {}});
  analysis::LoadCase shear;
  shear.id = "L2";
  shear.tractions.push_back({analysis::parse_side("u1"), Eigen::Vector3d(0, 300.0, 0), {}});
  problem.load_cases = {tension, shear};
  return problem;
}

/// nx x ny markers per load case on a grid strictly inside the plate, zero displacement.
inline std::vector<Marker> grid_markers(const analysis::Problem& problem, int nx = 12, int ny = 6) {
  std::vector<Marker> markers;
  int row = 2;
  for (const auto& load : problem.load_cases)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        Marker m;
        m.load_case = load.id;
        m.position = Eigen::Vector3d(0.1 * (i + 0.5) / nx, 0.04 * (j + 0.5) / ny, 0.0);
        m.row = row++;
        markers.push_back(m);
      }
  return markers;
}

inline void add_noise(std::vector<Marker>& markers, const std::vector<Eigen::Vector3d>& truth,
                      double sigma, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  for (size_t m = 0; m < markers.size(); ++m) {
    markers[m].displacement = truth[m];
    markers[m].displacement.x() += noise(rng);
    markers[m].displacement.y() += noise(rng);
  }
}

}  // namespace isospring::fitting::testing
