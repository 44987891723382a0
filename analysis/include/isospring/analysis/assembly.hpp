#pragma once
// Global matrices and load vectors of the IGA discretisation.
//
// Matrices are symmetric and stored as their UPPER triangle only (column-major); use
// `K.selfadjointView<Eigen::Upper>()` for products or `Eigen::SparseMatrix<double> full =
// K.selfadjointView<Eigen::Upper>();` for the full matrix. Element loops use Gauss quadrature with
// Problem::quadrature_points per direction (0: degree + 1), cached univariate B-spline values
// and run in parallel over an element colouring (elements of one colour share no node).
#include <Eigen/Sparse>
#include <vector>

#include "isospring/analysis/dof_map.hpp"
#include "isospring/analysis/problem.hpp"

namespace isospring::analysis {

/// Stiffness (upper triangle). Throws nurbs::InputError naming the patch, element and parameter
/// where the Jacobian determinant is not positive (an inverted or degenerate parametrisation).
Eigen::SparseMatrix<double> assemble_stiffness(const Problem& problem, const DofMap& dofs);
/// Consistent mass rho * int R_a R_b (times the thickness in 2D), upper triangle.
Eigen::SparseMatrix<double> assemble_consistent_mass(const Problem& problem, const DofMap& dofs);

/// Row-sum lumped mass per patch per control point: m_a = rho int R_a dV (times the thickness in
/// 2D). NURBS basis functions are non-negative, so every mass is >= 0 and they sum to rho * volume.
/// A node shared by glued patches carries the sum of its patches' entries.
std::vector<std::vector<double>> lumped_mass(const Problem& problem);
/// The same, summed per node of `dofs`.
Eigen::VectorXd lumped_node_mass(const Problem& problem, const DofMap& dofs);

/// External force vector of a load case (tractions, pressures, body force, gravity, point
/// loads); supports are not applied here.
Eigen::VectorXd assemble_load(const Problem& problem, const DofMap& dofs, const LoadCase& load);

/// Volume (area times thickness in 2D) of the model, by the same quadrature as the matrices.
double model_volume(const Problem& problem);

}  // namespace isospring::analysis
