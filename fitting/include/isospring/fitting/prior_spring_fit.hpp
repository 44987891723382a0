#pragma once
// One stiffness per spring fitted to MANY load cases at once, pulled towards a prior.
//
// Objective, theta_s = log k_s:
//   F(theta) = 1/2 mean_c (%e_rms,c / 100)^2 + 1/2 (w / S) sum_s (theta_s - log prior_s)^2
// over the C fitted cases and S springs. The data term is the displacement objective of
// displacement_fit.hpp averaged over the cases (so w means the same for 3 or 30 cases); the
// penalty chooses, among stiffness sets that fit equally well, the one closest to the prior
// (typically the grouped optimum) and is what keeps a per-spring model from interpolating the
// fitted loads at the expense of all others. w is chosen by validation error, not here.
//
// Why not the Levenberg-Marquardt of displacement_fit.hpp: with C cases the residuals number
// C x (nodes x dim); for a 2000-spring solid and ~15 cases both the primal (S x S) and the dual
// (residual-sized) LM systems cost tens of GFlop per iteration. The gradient of F needs one
// factorisation of K and two solves per case (the adjoint: dF/dk_s = -mean_c (g_s . lambda_c)
// (g_s . u_c), lambda_c = K^-1 P^T s_c r_c), so L-BFGS (Ceres GradientProblemSolver) is cheap per
// iteration whatever C and S.
#include <string>
#include <vector>

#include "isospring/fitting/displacement_fit.hpp"

namespace isospring::fitting {

// With volume terms (network.volumes, spring_volume.hpp) every term's modulus is one more
// parameter like a spring's stiffness (rank-one element kappa/|V0| b b^T, S counts both).
struct PriorSpringFitOptions {
  /// Per spring, then per volume term, > 0: the start and the target of the penalty.
  std::vector<double> prior;
  double weight = 1e-4;  // w >= 0
  int max_iterations = 400;
  double function_tolerance = 1e-9;  // relative change of F that ends the fit
};

struct PriorSpringFitResult {
  std::vector<double> spring_stiffness;
  std::vector<double> volume_modulus;                // per volume term
  std::vector<double> percent_e_rms, percent_e_max;  // per fitted case, control points
  double cost = 0.0;                                 // F at the end
  int iterations = 0;
  bool converged = false;  // Ceres ended on a tolerance, not on the iteration limit or a failure
  std::string message;
  double seconds = 0.0;
};

/// Throws nurbs::InputError for inconsistent data (prior size, non-positive prior, a case with
/// zero reference displacement) and std::runtime_error when K(prior) is singular.
PriorSpringFitResult fit_springs_with_prior(const DisplacementFitData& data,
                                            const PriorSpringFitOptions& options);

}  // namespace isospring::fitting
