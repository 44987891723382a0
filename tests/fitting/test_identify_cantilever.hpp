#pragma once
// A plane-strain cantilever for the large-deformation identification tests: [0, 1] x [0, 0.1] m,
// 16 x 2 quadratic elements, clamped at x = 0, two load cases on x = L (a downward shear traction
// q, and an upward one of q / 2 with an axial pull of q / 4; at q = 450 Pa and E = 1.15e6 Pa the
// first deflects the tip by 14 % of the length), and 20 x 3 markers along the beam per load case.
#include <vector>

#include "isospring/analysis/problem.hpp"
#include "isospring/fitting/measure.hpp"
#include "test_identify_plate.hpp"

namespace isospring::fitting::testing {

constexpr double kCantileverLength = 1.0, kCantileverDepth = 0.1;
constexpr double kCantileverPriorE = 1e6, kCantileverNu = 0.3;

inline analysis::Problem two_load_cantilever(double q) {
  analysis::Problem problem;
  problem.patches.push_back(rectangle(kCantileverLength, kCantileverDepth, 16, 2));
  problem.formulation = analysis::Formulation::kPlaneStrain;
  problem.material.youngs_modulus = kCantileverPriorE;
  problem.material.poisson_ratio = kCantileverNu;
  problem.material.thickness = 1.0;
  analysis::Support clamp;
  clamp.side = analysis::parse_side("u0");
  clamp.fixed = {true, true, false};
  problem.supports.push_back(clamp);
  analysis::LoadCase down, up;
  down.id = "down";
  down.tractions.push_back({analysis::parse_side("u1"), Eigen::Vector3d(0, -q, 0), {}});
  up.id = "up";
  up.tractions.push_back({analysis::parse_side("u1"), Eigen::Vector3d(q / 4, q / 2, 0), {}});
  problem.load_cases = {down, up};
  return problem;
}

inline std::vector<Marker> beam_markers(const analysis::Problem& problem) {
  std::vector<Marker> markers;
  for (const analysis::LoadCase& load : problem.load_cases)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 20; ++i) {
        Marker m;
        m.load_case = load.id;
        m.position = Eigen::Vector3d(kCantileverLength * (i + 0.5) / 20,
                                     kCantileverDepth * (j + 0.5) / 3, 0.0);
        m.row = static_cast<int>(markers.size()) + 2;
        markers.push_back(m);
      }
  return markers;
}

}  // namespace isospring::fitting::testing
