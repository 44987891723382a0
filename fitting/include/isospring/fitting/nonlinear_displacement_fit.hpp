#pragma once
// The displacement objective of displacement_fit.hpp with the spring model's NONLINEAR static
// equilibrium as its response: u_c(k) solves f_c + f_int(x0 + u_c; k) = 0 with the exact spring,
// volume and shear forces (analysis/spring_mechanics.hpp), so stiffnesses are fitted where the
// network actually goes under large loads instead of about its rest state.
//
// Residuals are those of displacement_residuals (r_c,a = (u_particle(a) - u_ref,a) / (o_max,c
// sqrt(n)), parameters theta = log k per group). Jacobian by the implicit function theorem at
// the equilibrium: the internal force is linear in every group's parameter, f_int = sum_g k_g
// phi_g(x), so with the tangent K_T = -d f_int / du,
//   du_c / d theta_g = K_T^-1 f_g(x_c),   f_g = k_g phi_g: the forces of group g alone.
// One factorisation of K_T per case and one solve per group. At rest (u -> 0) this is the
// linear fit's -K^-1 K_g u.
//
// Each case's equilibrium is found by Newton on the potential Pi(u) = E(x0 + u) - f . u from the
// equilibrium of the best (lowest-cost) point evaluated so far (the optimiser moves k a little
// per step; not the last evaluation, a rejected trial that may have left a case on another
// branch), falling back to load stepping from rest; where the tangent is indefinite it is
// shifted until positive definite and steps must lower Pi, so the equilibrium found is a stable
// one. A case that does not converge fails the evaluation and the optimiser shortens its step.
// The fit returns its best point unless, with every equilibrium from rest (as the model is
// evaluated and as an engine starts), the initial stiffnesses explain the cases better: then
// it returns those (and says so in `message`).
#include <Eigen/Core>

#include "isospring/fitting/displacement_fit.hpp"

namespace isospring::fitting {

/// Residuals and (when `jacobian` is not null) the analytic Jacobian of the nonlinear objective
/// at theta, from rest (no warm start). False when an equilibrium is not found or K_T is
/// singular.
bool nonlinear_displacement_residuals(const DisplacementFitData& data, const Grouping& grouping,
                                      const Eigen::VectorXd& theta, Eigen::VectorXd& residuals,
                                      Eigen::MatrixXd* jacobian);

/// Grouped fit (Ceres Levenberg-Marquardt, dense QR) of the nonlinear objective. Uses
/// options.grouping, initial (empty: the LINEAR fit of the same data, fit_displacements, which
/// the nonlinear fit then corrects), min_stiffness_ratio, max_iterations and on_iteration.
/// Throws nurbs::InputError for more than 64 groups (per-spring freedom is fitted linearly only)
/// or a regularisation, which this fit does not offer, and like fit_displacements otherwise.
DisplacementFitResult fit_displacements_nonlinear(const DisplacementFitData& data,
                                                  const DisplacementFitOptions& options);

/// The nonlinear static equilibrium u of `network` under `force` (flat particle forces) with
/// `constrained` DOFs (constrained_dofs: fixed particles plus extras) held at zero: Newton on the
/// potential (see above) from `start`, else from rest in 1, 4, 16 or 64 load steps. False when
/// it does not converge to |r| <= 1e-10 |f|.
bool spring_equilibrium(const analysis::SpringNetwork& network, const Eigen::VectorXd& force,
                        const std::vector<int>& extra_constrained, Eigen::VectorXd& u,
                        const Eigen::VectorXd& start = {});

}  // namespace isospring::fitting
