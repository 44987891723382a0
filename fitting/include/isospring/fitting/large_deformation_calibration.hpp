#pragma once
// Spring-model calibration at large deformation: the references are finite-strain IGA solutions
// (analysis::solve_static_nonlinear, neo-Hookean or SVK) of the fitted load cases at increasing
// amplitude, and the model's response is its nonlinear static equilibrium
// (nonlinear_displacement_fit.hpp), so the stiffnesses are fitted where the material goes.
//
// Amplitude: %eps_G, the mean |stretch| of the control net's springs (100 mean ||d + Delta|| -
// L0| / L0, Delta the change of the spring's vector) under the LINEAR IGA solution, the measure
// of [S15]'s "about 10 % deformation". Each fitted case is scaled to every amplitude (bisection:
// %eps_G is non-decreasing in the load factor) and solved nonlinearly at that load; the
// nonlinear solution's own %eps_G is reported beside it.
//
// Stages: linear references for the scaling; nonlinear references; calibrate() on the scaled
// cases with those references (mesh, masses, supports, gamma: a linear fit to the finite-strain
// data) and on their linear references; the nonlinear fit from whichever of the two explains
// the first amplitude better, continued in amplitude. At small amplitude the finite-strain
// reference and the spring equilibrium both tend to their linearisations, so the result tends to
// the linear calibration.
#include <string>
#include <vector>

#include "isospring/analysis/nonlinear_elasticity.hpp"
#include "isospring/fitting/calibration.hpp"

namespace isospring::fitting {

struct LargeDeformationSettings {
  analysis::HyperelasticMaterial law = analysis::HyperelasticMaterial::kNeoHookean;
  /// Target %eps_G of every fitted case (`calibration.amplitudes`), each > 0, ascending; every
  /// fitted case is fitted once per amplitude. The fit continues in amplitude: the cases up to
  /// the first amplitude, then up to the second from there, and so on.
  std::vector<double> amplitudes = {2.0, 10.0, 20.0};
};

/// A calibrated network and what its solves on the problem's load cases need.
struct SpringModelOnProblem {
  analysis::SpringNetwork network;
  std::vector<int> particle_of_node;   // DofMap node -> particle
  std::vector<int> extra_constrained;  // held particle components besides the fixed particles
};

/// One load case of the problem against the finite-strain reference.
struct LargeDeformationCase {
  std::string id;
  double load_factor = 1.0;    // times the load case as given
  double percent_eps_g = 0.0;  // %eps_G of the finite-strain reference
  bool solved = false;         // the spring model found an equilibrium (else control is empty)
  ErrorMetrics control;        // the model's nonlinear equilibrium on the control points
  std::vector<Eigen::Vector3d> node_error;  // u_model - u_ref per DofMap node (when solved)
};

struct LargeDeformationResult {
  /// calibrate() on the scaled cases against the finite-strain references (linear springs):
  /// the mesh, grouping and gamma, and the start of the nonlinear fit.
  CalibrationResult start;
  /// The nonlinear fit started from the linear calibration on LINEAR references of the same
  /// cases instead of `start`: it explained the first amplitude's finite-strain cases better by
  /// its nonlinear equilibrium (`start` keeps the mesh and grouping either way).
  bool started_from_linear_references = false;
  SpringModelOnProblem model;  // the nonlinear fit's stiffnesses
  DisplacementFitResult fit;   // the nonlinear fit
  /// Per fitted case and amplitude ("id@amplitude"), the model against its reference.
  std::vector<LargeDeformationCase> fitted;
  /// The largest amplitude fitted: the last of `amplitudes` unless at a later one the fit found
  /// no spring equilibrium or the fitted springs' equilibrium (from rest) under a fitted case
  /// inverts a net cell (V/V0 <= 0: the net folds through itself, which the solid's reference
  /// never does); then `stopped` says which case and the fit up to this one is kept.
  double reached_amplitude = 0.0;
  std::string stopped;
  /// The fitted cases as scaled and their finite-strain references, amplitude-major, up to the
  /// reached amplitude (ids "id@amplitude", as in `fitted`).
  std::vector<analysis::LoadCase> scaled_cases;
  std::vector<analysis::NonlinearLoadCaseResult> references;
  double reference_seconds = 0.0;  // linear and nonlinear IGA solves
  double fit_seconds = 0.0;        // linear start and nonlinear fit
};

/// The load case times `factor` (tractions, pressures, point loads, body force, gravity).
analysis::LoadCase scaled_load_case(const analysis::LoadCase& load_case, double factor,
                                    const std::string& id);

/// Per load case of `problem`: the factor that brings %eps_G of its linear IGA solution on the
/// spring mesh of `mesh` to `percent`. Throws std::runtime_error for a case that deforms nothing.
std::vector<double> load_factors_for_eps_g(const analysis::Problem& problem,
                                           const SpringMeshOptions& mesh, double percent);

/// The network, node map and supports of a calibration of `problem` (the linear one of today).
SpringModelOnProblem spring_model_of(const analysis::Problem& problem,
                                     const CalibrationResult& calibration);

/// Every load case of `problem` as forces on the model's particles (the nodes' consistent loads
/// summed onto the particle each node belongs to), in the order of problem.load_cases.
std::vector<Eigen::VectorXd> particle_loads(const analysis::Problem& problem,
                                            const SpringModelOnProblem& model);

/// Calibrates as described above: settings.fit_cases (empty: every case not in holdout_cases)
/// are scaled to every amplitude; gamma, gamma_sweep, mesh, mass model, bounds and iterations
/// come from `settings`; per-spring freedom, matrix approach and given references are refused.
/// Throws nurbs::InputError naming the field for bad input (calibration.amplitudes entries <= 0
/// or not ascending, a finite-strain law in plane stress) and std::runtime_error when a solve
/// fails (an amplitude where the spring model finds no equilibrium names that amplitude).
LargeDeformationResult calibrate_large_deformation(const analysis::Problem& problem,
                                                   const CalibrationSettings& settings,
                                                   const LargeDeformationSettings& large);

/// The finite-strain IGA solution (`law`) of every load case of `problem` (DofMap numbering).
/// Throws nurbs::InputError for plane stress and std::runtime_error when Newton fails.
std::vector<Eigen::VectorXd> finite_strain_references(const analysis::Problem& problem,
                                                      analysis::HyperelasticMaterial law);

/// Every load case of `problem` (its loads as given, e.g. held-out large loads) against its
/// reference (finite_strain_references), solved by the spring model's nonlinear equilibrium and
/// compared on the control points. A case where the springs find no equilibrium has
/// solved = false.
std::vector<LargeDeformationCase> evaluate_large_deformation(
    const analysis::Problem& problem, const SpringModelOnProblem& model,
    const std::vector<Eigen::VectorXd>& references);

}  // namespace isospring::fitting
