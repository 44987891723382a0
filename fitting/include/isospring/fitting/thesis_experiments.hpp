#pragma once
// The [S15] chapter-5 experiments (Table 5.1) as isospring problems, with a stated protocol:
// E = 15 kPa, nu = 1/3, rho = 1143 kg/m^3; exact geometry on open uniform knot vectors of degree
// p with (net - p) elements per direction and equally spaced control points (as S15's group
// counts imply: 2 rest lengths in the square, 3 in the cube); side u0 (x = 0) fixed in every
// component; load case "fit": a uniform traction on side u1 along the direction of S15's f_ext
// (square (1,-1,0), cube (2,-1,1)); held-out cases: traction on u1 along x only ("holdout_x") and
// on v1 along -y ("holdout_v1"); "fit_points": S15's f_ext (Table 5.2: square (200,-200,0), cube
// (80,-40,40)) as a force on every control point of side u1 ("traction on free control points").
// Membranes are plane stress with thickness 1. Errors are scale-invariant in the linear setting, so
// the traction magnitude (chosen for about 10% deformation) does not change them.
#include <string>
#include <vector>

#include "isospring/analysis/problem.hpp"

namespace isospring::fitting {

struct ThesisObject {
  std::string name;
  analysis::Problem problem;
  double published_e_rms = 0.0;  // Table 5.3 (or 5.4 for other net sizes; 0 when not published)
  double published_e_max = 0.0;
};

/// Square membrane 2 x 2 with an n x n net of degree `degree` (Table 5.1: n = 6, degree 2).
ThesisObject thesis_square(int n = 6, int degree = 2);
/// Cube 2 x 2 x 2 with an n^3 net of degree `degree` (Table 5.1: n = 6, degree 2).
ThesisObject thesis_cube(int n = 6, int degree = 2);

}  // namespace isospring::fitting
