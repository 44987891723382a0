#pragma once
// The measured-data loop: fit the nominal model (E, optionally nu) to marker displacements,
// then add effects (effect.hpp) one at a time while the best one is statistically significant,
// refitting everything each time.
//
// Selection: nested-model F-test. With RSS the weighted residual sum of squares, n the number of
// observations (markers x components) and p the number of parameters, adding an effect with q
// parameters gives F = ((RSS_0 - RSS_1) / q) / (RSS_1 / (n - p_1)); the effect with the smallest
// p-value is added when p < significance / (number of candidates tried in that round) (Bonferroni,
// so a round adds a spurious effect with probability <= significance on pure noise). After an
// addition, a backward step drops earlier effects whose removal F-test has p > significance
// (stepwise selection: an early effect may only have stood in for a later one). The F-test
// uses the residual variance of the larger model, so it needs no noise level.
//
// Discretisation control (discretization_check.hpp): after the nominal fit and before any effect
// is tried, the reference is solved on finer discretisations until its estimated error at the
// markers is below a third of the noise (or the DOF budget ends the ladder); the loop then runs on
// that level. When the budget ends it first, every F-test is widened: an effect must explain more
// than the weighted squared discretisation error that the material fit cannot absorb
// (discretization_allowance), so a model's own numerical error is never named as physics.
//
// Noise level: given, or estimated from the baseline residual by local linear fits: at every
// marker, a linear function of position is fitted to the residuals of it and its nearest
// neighbours (same load case), and the marker's misfit, divided by sqrt(1 - h) (h its leverage),
// is a sample of the noise; sigma = 1.4826 MAD over markers and components. The fit removes the
// smooth part of the residual (what the model misses) up to its curvature across a
// neighbourhood, where plain neighbour differences kept its gradient (measured on the suite's
// tube with undeclared self-weight: 2.7 x the true noise).
#include <Eigen/Core>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "isospring/analysis/problem.hpp"
#include "isospring/fitting/discretization_check.hpp"
#include "isospring/fitting/identify_diagnosis.hpp"
#include "isospring/fitting/measure.hpp"

namespace isospring::fitting {

struct IdentifyOptions {
  bool fit_poisson = false;
  double noise_sigma = 0.0;  // [m]; 0: estimate from the data
  double significance = 0.01;
  /// Threads of the element loops (the large-deformation candidate's assembly); 0: OpenMP's
  /// maximum at the call. Elements of one colour share no node and colours run in order, so the
  /// results are the same, digit for digit, for every count. Factorisations stay on one thread.
  int threads = 0;
  /// The effects to try; unset: the whole library (effect_names()); an empty list: none, the
  /// nominal fit alone (e.g. to reproduce a published plain fit before the loop adds effects).
  std::optional<std::vector<std::string>> candidates;
  /// Relative weights of the displacement components (x, y(, z)) on top of the noise level: rows
  /// of component c weigh component_weights[c] / sigma in every fit. Normalised to rms 1 over
  /// the model's components, so only their ratios matter. Empty: equal weights.
  std::vector<double> component_weights;
  /// Weights 1 / mean |u_c| over the measured displacements of component c (normalised as
  /// above): the per-component normalisation of Anton et al. (2024) for DIC data whose transverse
  /// displacements are much smaller than the axial ones. Excludes component_weights.
  bool component_weights_mean_abs = false;
  bool holdout = true;  // fit on even markers, validate on odd ones
  int max_effects = 6;
  DiscretizationOptions discretization;              // discretisation control before diagnosis
  std::function<void(const std::string&)> progress;  // progress lines (may be empty)
};

struct ParameterEstimate {
  std::string effect;  // "material" or the effect's name
  std::string name;
  std::string unit;
  double value = 0.0;
  double standard_error = 0.0;  // from the Gauss-Newton covariance (gauss_newton_covariance);
                                // NaN when the parameter is not identifiable
};

struct ErrorSummary {
  double rms = 0.0;  // sqrt(mean |r_c|^2) over every component of every marker [m]
  double max = 0.0;  // max |r_c| [m], the largest single component
  /// max |r| [m], the largest residual vector's length (the |residual| of residuals.csv and the
  /// marker .vtp files)
  double max_norm = 0.0;
};

struct LoadCaseErrors {
  std::string id;
  int markers = 0;
  ErrorSummary before, after;
};

struct CandidateTest {
  std::string effect;
  int parameters = 0;
  double rss = 0.0;  // weighted RSS of the refit with the candidate
  double f_statistic = 0.0;
  double p_value = 1.0;
  std::string note;      // why it was not tried (unavailable, fit failed)
  double seconds = 0.0;  // the refit's wall time
  /// The score test's F for expensive (nonlinear) candidates, NaN when not screened: such a
  /// candidate is fitted only when its score p-value is below 10 x the threshold.
  double score_f = std::numeric_limits<double>::quiet_NaN();
  /// Schwarz's criterion of the refit against the round's model: BIC = n ln(RSS / n) + k ln n
  /// (n weighted observations, k parameters); negative favours the candidate. Beside the F-test
  /// in the report, and the tie-break between candidates whose p-values both underflow to 0 (the
  /// RSS alone would then always favour the candidate with more parameters).
  double delta_bic = std::numeric_limits<double>::quiet_NaN();
  /// What the F-test and BIC discount from the candidate's RSS reduction (weighted RSS units):
  /// the part of the reference's estimated discretisation error at the markers that the
  /// candidate could absorb to first order, |P e|^2 + 4 |P e| (two standard deviations of its
  /// cross term with the noise), or the whole widening when the DOF budget was exhausted.
  double model_error_allowance = 0.0;
  /// The estimate of a parameter the effect's physics fixes (Effect::expected_values; the
  /// nonlinear blend weight w = 1), from the score test or the fit, and its standard error; the
  /// candidate is not added when they contradict the fixed value (see `note`). Empty name / NaN
  /// for effects without such a parameter.
  std::string expected_parameter;
  double expected_estimate = std::numeric_limits<double>::quiet_NaN();
  double expected_error = std::numeric_limits<double>::quiet_NaN();
};

struct SelectionRound {
  double rss = 0.0;              // before the round
  ResidualDescription residual;  // of the model before the round (identify_diagnosis.hpp)
  std::vector<CandidateTest> candidates;
  std::string added;                 // empty: none significant, the loop stopped
  std::vector<std::string> removed;  // earlier effects the backward step dropped
};

/// A non-nested alternative to the selected effects: one of them replaced by another candidate,
/// compared by BIC (the F-test needs nested models).
struct Alternative {
  std::string replaced, by;
  double delta_bic = 0.0;  // BIC(alternative) - BIC(selected); < 0 favours the alternative
  bool swapped = false;    // the selection took it (delta_bic < -2: positive evidence)
};

/// Leave-one-load-case-out: the nominal and the final model refitted without a load case, then
/// predicting it. Parameters that act on that load case alone (its own rigid motion, its load
/// factor) cannot be predicted and are fitted on it (a linear least-squares step: they enter
/// linearly); `local_parameters` counts them.
struct LoadCaseHoldout {
  std::string id;
  int markers = 0;
  int local_parameters = 0;
  ErrorSummary before, after;  // on the held-out load case
};

struct HoldoutCheck {
  int fit_markers = 0, validation_markers = 0;
  ErrorSummary validation_before, validation_after;  // on the validation markers
};

struct IdentifyResult {
  std::vector<std::string> effects_added;
  std::vector<ParameterEstimate> parameters;
  std::vector<ParameterEstimate> parameters_before;     // the nominal model's (no effects)
  std::vector<std::pair<std::string, double>> derived;  // e.g. support stiffness values
  std::vector<std::string> spring_model_notes;          // per added effect
  ErrorSummary before, after;
  ResidualDescription residual_before, residual_after;  // baseline and final residual
  double noise_estimate = 0.0;                          // [m]
  bool noise_given = false;
  double chi2_before = 0.0, chi2_after = 0.0;  // RSS / sigma^2 / (n - p)
  int observations = 0;
  std::vector<LoadCaseErrors> load_cases;
  std::vector<SelectionRound> rounds;
  /// The swap stage after the stepwise selection: every selected effect against every other
  /// linear candidate in its place. Swaps taken, and the alternatives the data cannot tell from
  /// the selection (|delta_bic| < 2): e.g. a stiff clamp and a per-load-case rigid motion.
  std::vector<Alternative> alternatives;
  /// The discretisation ladder (chosen_problem is the model the loop ran on when refined).
  DiscretizationCheck discretization;
  /// Weighted RSS subtracted from every candidate's RSS reduction in the F-tests: the estimated
  /// discretisation error at the markers (weighted by 1 / sigma) beyond what E absorbs; 0 when the
  /// reference met the target.
  double discretization_allowance = 0.0;
  HoldoutCheck holdout;
  bool holdout_done = false;
  std::vector<LoadCaseHoldout> load_case_holdout;  // with 2 or more load cases
  std::vector<double> component_weights;           // the weights used (one per component, rms 1)
  std::vector<Eigen::Vector3d> model_before, model_after;  // per marker, model displacement [m]
  double youngs_modulus = 0.0, poisson_ratio = 0.0;        // final material
  /// The added effects with their fitted values (parameter_names() order), as simulate_markers
  /// takes them.
  std::vector<std::pair<std::string, Eigen::VectorXd>> effect_values;
  /// The corrected reference: per load case, the final model's displacement at every DOF
  /// (analysis::DofMap numbering) with the identified material and physical effects; the
  /// measurement-frame effect (rigid_offset) is not part of it. Always on the DOFs of the problem
  /// passed in (the case's discretisation), also when the loop ran on a refined level.
  std::vector<Eigen::VectorXd> corrected_displacements;
  /// What the loop had to adapt: e.g. an immersed stiffness that needed more of the ghost
  /// penalty than its options' ghost_fraction (on the case's grid or the level chosen).
  std::vector<std::string> warnings;
  double seconds = 0.0;
};

/// Runs the loop. `markers` must all lie on the model with `placements` from place_markers; each
/// marker's load case must be one of problem.load_cases (nurbs::InputError otherwise).
IdentifyResult identify(const analysis::Problem& problem, const std::vector<Marker>& markers,
                        const std::vector<MarkerPlacement>& placements,
                        const IdentifyOptions& options = {});

/// Forward simulation for synthetic data and checks: the model displacement at every marker with
/// the problem's material and the given effects at the given parameter values (each effect's
/// parameters in its parameter_names() order).
std::vector<Eigen::Vector3d> simulate_markers(
    const analysis::Problem& problem, const std::vector<Marker>& markers,
    const std::vector<MarkerPlacement>& placements,
    const std::vector<std::pair<std::string, Eigen::VectorXd>>& effects);

/// (J^T J)^-1 of a weighted Jacobian J (rows: residuals / sigma, columns: parameters), computed
/// as D (J_s^T J_s)^+ D with J_s = J D, D = diag(1 / |column|): the column scaling removes the
/// parameters' units from the conditioning, so only genuine collinearity counts. Directions with
/// singular value below `relative_tolerance` times the largest of J_s are a null space; every
/// parameter that has a component > 1e-6 in it gets NaN variance (and covariances) instead of a
/// meaningless large number; a zero column is NaN too.
Eigen::MatrixXd gauss_newton_covariance(const Eigen::MatrixXd& weighted_jacobian,
                                        double relative_tolerance = 1e-10);

/// Upper tail of the F distribution: P(F(d1, d2) > f).
double f_test_p_value(double f, int d1, int d2);

/// The robust local-linear-fit noise estimate described above, from per-marker residual vectors
/// (only the first `dimension` components), markers grouped by `group`; 0 when no group has enough
/// markers for a fit with residual degrees of freedom.
double estimate_noise(const std::vector<Eigen::Vector3d>& positions,
                      const std::vector<Eigen::Vector3d>& residuals, const std::vector<int>& group,
                      int dimension);

}  // namespace isospring::fitting
