#pragma once
// The acceleration objective [S15 4.1-4.5] as a baseline beside the displacement objective and
// the matrix approach. [S15] takes a reference state x_ref with acceleration a_ref and asks the
// spring model to reproduce it: M a_ref = f_ext - f_int,NMSM(x_ref; k). Linearised at rest the
// spring forces are K_NMSM(k) u_ref = sum_s k_s g_s (g_s^T u_ref), LINEAR in k, so
//
//   min_{k >= 0}  sum_c || M^-1 ( A(u_ref,c) k - (f_c - M a_ref,c) ) ||^2 over the free DOFs,
//   column s of A(u) = g_s (g_s^T u)  (summed over the springs of a group),
//
// a bound-constrained linear least-squares problem solved directly (Lawson-Hanson active set,
// no starting point, no iterations of a nonlinear optimizer). The residual is an acceleration
// (M^-1 weighting) as in [S15]. isospring's references are static IGA solutions (a_ref = 0): the
// objective then asks K_NMSM(k) u_ref = f = K_IGA u_ref, i.e. the spring forces of the IGA
// displacement field match the IGA's internal forces at every free control point.
#include <string>
#include <vector>

#include "isospring/analysis/problem.hpp"
#include "isospring/fitting/calibration.hpp"
#include "isospring/fitting/displacement_fit.hpp"

namespace isospring::fitting {

struct AccelerationFitResult {
  std::vector<double> group_stiffness;   // per group, >= 0
  std::vector<double> spring_stiffness;  // per spring
  /// ||W (A k - b)|| / ||W b|| over all fitted cases (W = M^-1 or identity).
  double relative_residual = 0.0;
  int groups_at_zero = 0;  // groups the bound k >= 0 holds at zero
  double seconds = 0.0;
};

struct AccelerationFitOptions {
  Grouping grouping;
  /// Residuals are accelerations M^-1 (K u - f) [S15]; false: forces K u - f (unit weights).
  bool weight_by_mass = true;
};

/// Fits the group stiffnesses of `data.network` (rest geometry, masses, fixed particles) so that
/// the spring forces of the reference displacements data.references (per node, mapped through
/// data.particle_of_node) balance data.loads on every free DOF. Throws nurbs::InputError for
/// inconsistent sizes or non-positive masses (when weighting by mass).
AccelerationFitResult fit_accelerations(const DisplacementFitData& data,
                                        const AccelerationFitOptions& options);

/// min ||A x - b||, x >= 0 (Lawson & Hanson 1974, ch. 23). Columns are scaled to unit norm
/// internally. Exposed for its test.
Eigen::VectorXd nonnegative_least_squares(const Eigen::MatrixXd& a, const Eigen::VectorXd& b);

/// The acceleration baseline of a finished calibration: same problem, springs, masses, supports
/// and grouping as `calibrated` (for a per-spring calibration: the rest-length grouping of its
/// gamma, which it started from), references re-solved by the IGA; its model is evaluated on the
/// fitted and held-out cases like the displacement fit. Returned as a MatrixComparison with
/// method "acceleration" (fit.relative_residual: the acceleration residual above, not the
/// Frobenius residual; fit.negative_springs: springs held at k = 0).
MatrixComparison acceleration_baseline(const analysis::Problem& problem,
                                       const CalibrationSettings& settings,
                                       const CalibrationResult& calibrated);

}  // namespace isospring::fitting
