#pragma once
// The displacement objective [S15 5.7], generalised to several load cases and to one parameter
// per spring: minimise sum_c (%e_rms,c / 100)^2 over the stiffnesses, where the NMSM response is
// u(k) = K(k)^-1 f_c, K(k) = sum_s k_s g_s g_s^T linear in k.
//
// Residuals: r_c,a = (u_particle(a) - u_ref,a) / (o_max,c sqrt(n)) for every node a, so the sum of
// squares of case c is (%e_rms,c / 100)^2. Parameters theta with k = exp(theta) (positivity).
// Jacobian (analytic, no finite differences): du/dk_s = -K^-1 g_s (g_s^T u); one sparse Cholesky
// factorisation per evaluation (CHOLMOD supernodal; K's pattern, scatter map and symbolic
// analysis are built once per fit); the right-hand sides are solved column by column when there
// are few parameters, or through K^-1 (the adjoint form) when there are many.
//
// Solvers: up to 64 parameters (grouped fits), Ceres' Levenberg-Marquardt with dense QR. More
// (per-spring fits: parameters outnumber residuals, J^T J is rank-deficient) a box-bounded LM
// whose step comes from the residual-sized system (a I + J J^T) (src/dual_levenberg_marquardt.hpp):
// the 6^3 cube's 1940-spring fit converges in tens of iterations instead of Ceres CGNR's ~1200.
#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "isospring/analysis/spring_network.hpp"
#include "isospring/fitting/stiffness_groups.hpp"

namespace isospring::fitting {

/// Everything the objective needs, in the particle numbering of the network. Reference
/// displacements are per node (a control point after interface gluing) and mapped to particles by
/// `particle_of_node` (several nodes may share a particle when coincident points were merged).
struct DisplacementFitData {
  analysis::SpringNetwork network;    // rest geometry, fixed particles
  std::vector<int> constrained_dofs;  // extra particle DOFs held at zero (symmetry supports)
  std::vector<int> particle_of_node;
  std::vector<Eigen::VectorXd> loads;       // per case: particle forces, flat (particle * dim + c)
  std::vector<Eigen::VectorXd> references;  // per case: node displacements, flat (node * dim + c)
};

struct DisplacementFitOptions {
  /// Parameters: one stiffness per group (springs [N/m]; volume-term groups: the modulus kappa
  /// [Pa], spring_volume.hpp, started at E / 4 when `initial` is empty).
  Grouping grouping;
  std::vector<double> initial;       // per group; empty: a scaled E * L0 guess (see .cpp)
  std::vector<double> upper_bounds;  // per group; empty: none
  /// Every stiffness is bounded below by this fraction of the largest initial group stiffness
  /// (or by the smallest initial stiffness when that is lower: a given start is never moved).
  /// Log-parameters alone only keep k > 0: a group that the data would rather switch off drifts
  /// towards k = 0, K(k) becomes numerically singular and its solves turn to noise. A spring
  /// 1e-6 times softer than the network's stiffest contributes nothing measurable, so the bound
  /// costs no accuracy while keeping cond(K) within ~1e6 of the rest network's.
  double min_stiffness_ratio = 1e-6;
  /// > 0: every parameter is pulled towards a shared value per `regularization_groups` group
  /// by residuals sqrt(w) (theta_s - phi_group), the shared values free (w -> infinity recovers
  /// the grouped fit). It picks, among the near-optimal per-spring stiffness sets (more springs
  /// than residuals), one close to a grouping; without it a per-spring fit usually interpolates
  /// the fitted cases exactly.
  double regularization = 0.0;
  Grouping regularization_groups;
  int max_iterations = 200;
  double youngs_modulus = 1.0;  // scale of the initial guess
  /// Called after every Levenberg-Marquardt iteration with its number and the Ceres cost (progress
  /// lines); empty: silent.
  std::function<void(int iteration, double cost)> on_iteration;
};

struct DisplacementFitResult {
  std::vector<double> group_stiffness;   // per group
  std::vector<double> spring_stiffness;  // per spring
  std::vector<double> volume_modulus;    // per volume term (network.volumes), when any
  std::vector<double> percent_e_rms;     // per case, control points
  std::vector<double> percent_e_max;     // per case, control points
  int groups_at_lower_bound = 0;         // groups the fit pushed onto min_stiffness_ratio
  double cost = 0.0;                     // Ceres cost: 1/2 sum of squared residuals
  int iterations = 0;
  bool converged = false;
  std::string message;       // Ceres' report line (termination reason)
  double seconds = 0.0;      // wall clock
  double cpu_seconds = 0.0;  // process CPU time (the machine may be shared: wall time varies)
};

/// Residuals of the displacement objective at theta (k_group = exp(theta)) and, when `jacobian`
/// is not null, its analytic Jacobian with respect to theta (rows: residuals, columns: groups).
/// Returns false (a failed evaluation the optimiser recovers from by shortening its step) when a
/// stiffness exp(theta) or a displacement is not finite, or K(k) is not positive definite (a
/// mechanism).
bool displacement_residuals(const DisplacementFitData& data, const Grouping& grouping,
                            const Eigen::VectorXd& theta, Eigen::VectorXd& residuals,
                            Eigen::MatrixXd* jacobian);

/// spring_stiffness followed by volume_modulus: one value per parameter of one_group_per_spring()
/// (the start of a per-spring fit).
std::vector<double> per_element_values(const DisplacementFitResult& fit);

/// Number of residuals of displacement_residuals().
int num_displacement_residuals(const DisplacementFitData& data);

/// Fits with Ceres (Levenberg-Marquardt). Throws nurbs::InputError for inconsistent data (sizes,
/// a case with zero reference displacement) and std::runtime_error when the fit cannot start.
DisplacementFitResult fit_displacements(const DisplacementFitData& data,
                                        const DisplacementFitOptions& options);

}  // namespace isospring::fitting
