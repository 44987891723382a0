#pragma once
// The matrix approach [NC10, S15 3.17]: spring stiffnesses that make the NMSM stiffness matrix
// closest to the reference one in the Frobenius norm,
//
//   min_k || K_ref - sum_g k_g G_g ||_F,   G_g = sum_{s in group g} g_s g_s^T.
//
// K_NMSM is linear in k, so this is a linear least-squares problem: its normal equations
// <G_g, G_h>_F k_h = <G_g, K_ref>_F are solved directly (no iterations, no starting point).
// The problem is unconstrained, so a stiffness may come out negative; it is reported, not hidden.
//
// Global: K_ref is the whole IGA stiffness (every DOF, no supports) mapped to the particles.
// Per element [NC10]: every net cell of a degree-1 patch is a bilinear/trilinear finite element;
// its own springs (the cell's edges, face and body diagonals) are fitted to its element matrix and
// shared springs sum their cells' values.
#include <vector>

#include "isospring/analysis/problem.hpp"
#include "isospring/fitting/spring_mesh.hpp"
#include "isospring/fitting/stiffness_groups.hpp"

namespace isospring::fitting {

struct MatrixFitResult {
  std::vector<double> group_stiffness;   // per group (global fit); empty for per element
  std::vector<double> spring_stiffness;  // per spring
  /// ||K_ref - K_NMSM(k)||_F / ||K_ref||_F over the whole particle matrix.
  double relative_residual = 0.0;
  int negative_springs = 0;  // springs with k < 0 (the fit is unconstrained)
  double seconds = 0.0;
};

/// Global Frobenius fit with one stiffness per group of `grouping`.
MatrixFitResult fit_stiffness_matrix(const analysis::Problem& problem, const SpringMesh& mesh,
                                     const Grouping& grouping);

/// Element-by-element Frobenius fit [NC10]. Throws nurbs::InputError unless every patch has
/// degree 1 in every direction (only then is a net cell an element).
MatrixFitResult fit_stiffness_matrix_per_element(const analysis::Problem& problem,
                                                 const SpringMesh& mesh);

/// ||K_ref - K_NMSM(k)||_F / ||K_ref||_F for given spring stiffnesses.
double relative_matrix_residual(const analysis::Problem& problem, const SpringMesh& mesh,
                                const std::vector<double>& spring_stiffness);

}  // namespace isospring::fitting
