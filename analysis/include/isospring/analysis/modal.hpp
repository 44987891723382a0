#pragma once
// Lowest natural modes K x = omega^2 M x (supports fix their DOFs to zero).
#include <Eigen/Core>
#include <Eigen/Sparse>
#include <vector>

#include "isospring/analysis/problem.hpp"

namespace isospring::analysis {

struct ModalOptions {
  int modes = 6;
  bool lumped_mass = false;  // row-sum lumped instead of consistent mass
};

struct ModalResult {
  Eigen::VectorXd eigenvalues;     // omega^2 [1/s^2], ascending
  Eigen::VectorXd frequencies_hz;  // omega / (2 pi)
  Eigen::MatrixXd shapes;          // global DOF vectors (DofMap numbering), M-orthonormal
  int dofs = 0;
};

/// Spectra's shift-invert Lanczos with a CHOLMOD factorisation of K - sigma M, sigma slightly
/// below zero so that unsupported (free-free) models work too (their rigid modes come out ~0).
/// Needs density > 0. Throws std::runtime_error when the eigensolver does not converge.
ModalResult compute_modes(const Problem& problem, const ModalOptions& options = {});

struct GeneralizedModes {
  Eigen::VectorXd eigenvalues;  // ascending
  Eigen::MatrixXd vectors;      // columns, M-orthonormal
};

/// The `count` lowest eigenpairs of K x = lambda M x for sparse symmetric K (positive
/// semi-definite) and M (positive definite), of which only the upper triangles are read: the
/// shift-invert Lanczos of compute_modes, for any such pair (a spring network's K and M too).
/// `tolerance`: Spectra's relative convergence tolerance of the Ritz values (a basis for a
/// reduced model needs the span, not 12 digits of each eigenvalue). Throws nurbs::InputError when
/// count is not in 1 .. rows - 1, std::runtime_error when the eigensolver does not converge.
GeneralizedModes lowest_generalized_modes(const Eigen::SparseMatrix<double>& k,
                                          const Eigen::SparseMatrix<double>& m, int count,
                                          double tolerance = 1e-12);

}  // namespace isospring::analysis
