#pragma once
// B-bar for the immersed path: the volumetric strain replaced by its mean over each cell's part
// (mean dilatation, one constraint per cell).
//
// Why this projection. The body-fitted B-bar (volumetric_projection.hpp) projects div u onto
// splines of one degree lower on the same knots. On a cut grid those splines would need the
// part's Gram matrix over cells that hold slivers of it (ill-conditioned, and coupling every
// cell's neighbours). The mean over a cell's part needs only the part's volume there, which is
// positive on every active cell, so the operator stays local to the cell (the stiffness keeps
// the displacement form's pattern) and has no conditioning issue of its own. It imposes one
// volumetric constraint per cell, as the degree p - 1 splines do (about one function per
// element), against about dim displacement DOFs per cell, so a nearly incompressible part no
// longer locks (tests: immersed Lame cylinder at nu 0.49 and 0.4999). The pressure is then
// piecewise constant, accurate to O(h) only: the energy error is O(h^2) at any degree instead of
// O(h^2p), so it is meant for p = 2 near nu = 0.5, not for high order.
//
// The energy is mu |dev eps|^2 + kappa / 2 theta_K^2 with the 3D deviator (plane strain:
// eps_zz = 0), kappa = lambda + 2 mu / 3 and theta_K the mean of div u over cell K's part: the
// cell kernel runs with lambda replaced by -2 mu / 3 and kappa b b^T / V_K is added, b the
// cell's integral of the basis divergences. Nitsche's supports use the same stress, 2 mu dev eps
// + kappa theta_K I, so the method stays symmetric and its penalty (a local eigenvalue estimate
// against this energy) keeps it coercive.
#include <Eigen/Core>

#include "immersed_kernels.hpp"
#include "volumetric_projection.hpp"

namespace isospring::analysis::detail {

/// theta_K as a row over the cell's local DOFs (a * dim + c, the basis order of
/// BasisAt): theta_K = row . q for the cell's displacement coefficients q.
Eigen::RowVectorXd cell_mean_divergence(const ImmersedContext& context, size_t cell);

/// Adds kappa b b^T / V_K to the cell's local stiffness, from the cell's weighted gradients WG
/// (points x count * dim, column k * count + a, weights times the thickness) as cell_stiffness
/// builds them.
void add_mean_dilatation(const ImmersedContext& context, const Eigen::MatrixXd& weighted_gradients,
                         double volume, Eigen::MatrixXd& local);

/// The traction operator sigma_bar(v) n (dim x count * dim) at a point of cell K with basis
/// gradients `gradients`: 2 mu dev eps n + kappa theta_K n, theta_K from cell_mean_divergence.
Eigen::MatrixXd bbar_traction_operator(const ImmersedContext& context,
                                       const Eigen::Vector3d& normal,
                                       const Eigen::MatrixXd& gradients,
                                       const Eigen::RowVectorXd& mean_divergence);

/// 1/2 of the B-bar energy of the result over the domain's cells (times the thickness in 2D).
double bbar_strain_energy(const geometry::ImmersedDomain& domain, const ImmersedResult& result,
                          const ImmersedOptions& options);

}  // namespace isospring::analysis::detail
