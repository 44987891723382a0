// The identification loop: its stages in order (loop_state.hpp), and the first four: the
// nominal fit, the discretisation check, the nominal fit where the loop runs and the candidates.
#include "isospring/fitting/identify.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <optional>

#include "identify/loop_state.hpp"
#include "isospring/analysis/thread_scope.hpp"
#include "isospring/nurbs/error.hpp"
#include "quiet_solver_warnings.hpp"

namespace isospring::fitting {

namespace identify_loop {

namespace {

// The nominal model's fit under uniform weights at the provisional noise level.
Fit nominal_fit(const Setup& setup, const Model& nominal, double provisional,
                const std::vector<bool>& all_markers) {
  const Fit fit = run_fit(setup, nominal, make_weights(setup, provisional, all_markers));
  if (!fit.ok) throw std::runtime_error("the nominal model's fit failed: " + fit.message);
  return fit;
}

// The noise level the discretisation check compares the reference's error with: the given one,
// the per-marker sigmas' rms, else the data's own estimate; per the most precise component.
double noise_for_discretisation(const LoopInputs& in, const CaseNominal& case_nominal) {
  const Setup& case_setup = case_nominal.setup;
  double noise = in.options.noise_sigma;
  if (!(noise > 0.0)) {  // per-marker sigmas, else the data's own estimate
    double sum = 0.0;
    int given = 0;
    for (const Marker& marker : in.markers)
      if (marker.sigma > 0.0) sum += marker.sigma * marker.sigma, ++given;
    if (given > 0) noise = std::sqrt(sum / given);
  }
  const double max_weight = case_setup.component_weight.head(case_setup.dim).maxCoeff();
  // A noise level estimated from the data on the case's own discretisation: the local linear
  // fits of the estimator remove the smooth misfit of a coarse model (measured within 1.21 x
  // the true noise on models 2 to 81 noise levels off the converged solution:
  // DiscretizationCheck.NoiseEstimatedOnCoarseModelsStaysNearTheTruth).
  if (!(noise > 0.0)) {
    const MarkerResidual case_residual =
        marker_residual(case_setup, case_nominal.baseline, case_nominal.fit.theta, in.markers);
    noise = weighted_noise(case_setup, case_residual.positions, case_residual.residual,
                           case_residual.group);
  }
  if (!(noise > 0.0)) noise = case_nominal.provisional;
  // The reference must be accurate enough for the most precise component (sigma / max w_c).
  return noise / max_weight;
}

// Widening when the reference could not be made accurate enough: the weighted squared
// discretisation error at the markers, less the part a refit of E absorbs (a common scale of
// the nominal predictions), is what an effect could explain without being physical.
double discretisation_allowance(const LoopInputs& in, const Setup& setup, const Nominal& nominal,
                                const IdentifyResult& result) {
  const DiscretizationCheck& disc = result.discretization;
  if (!(disc.done && !disc.within_target && disc.marker_error.size() == in.markers.size()))
    return 0.0;
  const int dim = setup.dim;
  double ee = 0.0, eu = 0.0, uu = 0.0;
  for (size_t l = 0; l < setup.markers.size(); ++l)
    for (size_t k = 0; k < setup.markers[l].size(); ++k)
      for (int c = 0; c < dim; ++c) {
        const auto m = static_cast<size_t>(setup.markers[l][k]);
        const double w = nominal.weights[l][static_cast<Eigen::Index>(k) * dim + c];
        const double e = w * disc.marker_error[m][c], u = w * result.model_before[m][c];
        ee += e * e, eu += e * u, uu += u * u;
      }
  const double allowance = std::max(0.0, uu > 0.0 ? ee - eu * eu / uu : ee);
  in.say(
      "the reference's discretisation error exceeds a third of the noise within the DOF "
      "budget; every F-test is widened by it (weighted RSS " +
      std::to_string(allowance) + ")");
  return allowance;
}

}  // namespace

// Stage 1. The case's discretisation first: the nominal fit there gives the material and the
// noise level that the discretisation check compares the reference's own error with.
void fit_case_nominal(const LoopInputs& in, CaseNominal& out) {
  if (in.custom_setup)
    in.custom_setup(out.setup);
  else
    make_setup(out.setup, in.problem, in.markers, in.placements, in.options.fit_poisson,
               in.progress());
  out.setup.context.threads = in.element_threads;
  out.setup.component_weight = component_weights(in.options, in.markers, out.setup.dim);
  // A provisional noise level makes the residuals O(1) for the solver's tolerances; uniform
  // weights do not change the estimate.
  double rms_data = 0.0;
  for (const auto& m : out.setup.measured) rms_data += m.squaredNorm();
  int total_rows = 0;
  for (const auto& m : out.setup.measured) total_rows += static_cast<int>(m.size());
  rms_data = std::sqrt(rms_data / std::max(1, total_rows));
  out.provisional =
      in.options.noise_sigma > 0.0 ? in.options.noise_sigma : std::max(1e-3 * rms_data, 1e-300);
  in.say("fitting the nominal model");
  out.baseline = build_model(out.setup, {}, Eigen::VectorXd());
  out.fit = nominal_fit(out.setup, out.baseline, out.provisional, in.all_markers);
}

// Stage 2: discretisation control before diagnosis, at the material of the nominal fit.
void choose_discretisation(const LoopInputs& in, const CaseNominal& case_nominal,
                           IdentifyResult& result, Discretisation& out) {
  const IdentifyOptions& options = in.options;
  if (!options.discretization.enabled) {
    result.discretization.note = "turned off";
    return;
  }
  if (in.custom_setup && !in.custom_check) {
    result.discretization.note = in.no_discretisation_check;
    return;
  }
  const double noise = noise_for_discretisation(in, case_nominal);
  const Eigen::VectorXd& theta = case_nominal.fit.theta;
  if (in.custom_check) {
    out.refined_setup = in.custom_check(case_nominal.setup, theta, noise, result.discretization);
    if (!out.refined_setup) return;
    out.refined_setup->context.threads = in.element_threads;
    out.refined_setup->component_weight = case_nominal.setup.component_weight;
    return;
  }
  const double nu = options.fit_poisson ? theta[1] : in.problem.material.poisson_ratio;
  const double youngs_modulus = in.problem.material.youngs_modulus * theta[0];
  result.discretization =
      check_discretization(in.problem, in.markers, in.placements, youngs_modulus, nu, noise,
                           options.discretization, in.progress());
  if (!result.discretization.chosen_problem) return;
  out.refined_problem = std::move(result.discretization.chosen_problem);
  result.discretization.chosen_problem.reset();
  out.refined_setup = std::make_unique<Setup>();
  make_setup(*out.refined_setup, *out.refined_problem, in.markers, in.placements,
             options.fit_poisson, in.progress());
  out.refined_setup->context.threads = in.element_threads;
  out.refined_setup->component_weight = case_nominal.setup.component_weight;
}

// Stage 3: the nominal model where the loop runs, its residual, the noise level and the
// selection's weights.
void fit_nominal(const LoopInputs& in, const CaseNominal& case_nominal,
                 const Discretisation& chosen, IdentifyResult& result, Nominal& out) {
  const Setup& setup = loop_setup(case_nominal, chosen);
  const bool refined = chosen.refined_setup != nullptr;
  if (refined) out.refined_baseline = build_model(setup, {}, Eigen::VectorXd());
  out.baseline = refined ? &*out.refined_baseline : &case_nominal.baseline;
  out.fit = refined ? nominal_fit(setup, *out.baseline, case_nominal.provisional, in.all_markers)
                    : case_nominal.fit;
  out.residual = marker_residual(setup, *out.baseline, out.fit.theta, in.markers);
  result.model_before = out.residual.predicted;
  result.before = summarize(out.residual.residual, in.all_rows, setup.dim);
  for (const auto& load : in.problem.load_cases) out.case_ids.push_back(load.id);
  result.residual_before = describe(setup, out, out.residual.residual);
  result.noise_given = in.options.noise_sigma > 0.0;
  result.noise_estimate = result.noise_given
                              ? in.options.noise_sigma
                              : weighted_noise(setup, out.residual.positions, out.residual.residual,
                                               out.residual.group);
  if (!(result.noise_estimate > 0.0)) result.noise_estimate = case_nominal.provisional;
  out.weights = make_weights(setup, result.noise_estimate, in.all_markers);
}

// Stage 4: the candidates (their matrices assembled once) and what their F-tests are widened by.
void collect_candidates(const LoopInputs& in, const Setup& setup, const Nominal& nominal,
                        IdentifyResult& result, Candidates& out) {
  result.discretization_allowance = discretisation_allowance(in, setup, nominal, result);
  out.allowance = result.discretization_allowance;
  const std::vector<std::string> names =
      in.options.candidates ? *in.options.candidates : effect_names();
  for (const std::string& name : names) {
    // Large deformation is the displacement formulation's SVK (no F-bar): on a B-bar reference
    // its remainder against the B-bar linear stiffness would not be O(|u|^2), so it is not
    // offered rather than fitted as something else.
    if (name == "geometric_nonlinearity" && setup.context.problem &&
        setup.context.problem->volumetric == analysis::Volumetric::kBbar) {
      out.unavailable.push_back(name +
                                ": the reference uses B-bar (nearly incompressible material), "
                                "and large deformation is implemented for the displacement "
                                "formulation only");
      continue;
    }
    std::string why;
    auto effect = make_effect(name, setup.context, &why);
    if (effect)
      out.library.push_back(std::move(effect));
    else
      out.unavailable.push_back(name + ": " + why);
  }
  // The model's own error at the observations (per load case, rows as measured): the
  // discretisation check's estimate at the level used. Whatever part of it a candidate could
  // absorb is not evidence for that candidate: its F-test is widened by it (fit_candidate).
  const DiscretizationCheck& disc = result.discretization;
  if (!(disc.done && disc.marker_error.size() == in.markers.size())) return;
  for (size_t l = 0; l < setup.measured.size(); ++l) {
    Eigen::VectorXd e(setup.measured[l].size());
    for (Eigen::Index k = 0; k < e.size(); ++k)
      e[k] = disc.marker_error[static_cast<size_t>(
          setup.markers[l][static_cast<size_t>(k / setup.dim)])][k % setup.dim];
    out.model_error.push_back(e);
  }
}

ResidualDescription describe(const Setup& setup, const Nominal& nominal,
                             const std::vector<Eigen::Vector3d>& residual) {
  return describe_residual(nominal.residual.positions, residual, nominal.residual.group,
                           nominal.case_ids, setup.nominal_loads, setup.dim, setup.context.centre,
                           setup.context.length);
}

std::vector<Eigen::Vector3d> simulate_with_effects(
    Setup& setup, size_t markers,
    const std::vector<std::pair<std::string, Eigen::VectorXd>>& effects,
    const std::string& caller) {
  std::vector<std::unique_ptr<Effect>> owned;
  std::vector<const Effect*> chosen;
  Eigen::VectorXd theta = Eigen::VectorXd::Ones(1);
  for (const auto& [name, values] : effects) {
    std::string why;
    owned.push_back(make_effect(name, setup.context, &why));
    if (!owned.back()) throw nurbs::InputError("effect " + name + " does not apply: " + why);
    if (values.size() != owned.back()->num_parameters())
      throw std::invalid_argument(caller + ": " + name + " takes " +
                                  std::to_string(owned.back()->num_parameters()) + " parameters");
    chosen.push_back(owned.back().get());
    theta.conservativeResize(theta.size() + values.size());
    theta.tail(values.size()) = values;
  }
  const Model model = build_model(setup, chosen, theta);
  return marker_predictions(setup, model, theta, markers);
}

}  // namespace identify_loop

IdentifyResult identify(const analysis::Problem& problem, const std::vector<Marker>& markers,
                        const std::vector<MarkerPlacement>& placements,
                        const IdentifyOptions& options) {
  using namespace identify_loop;
  std::vector<int> all_rows(markers.size());
  for (size_t m = 0; m < markers.size(); ++m) all_rows[m] = static_cast<int>(m);
  const LoopInputs in{problem,
                      markers,
                      placements,
                      options,
                      options.threads > 0 ? options.threads : omp_get_max_threads(),
                      std::vector<bool>(markers.size(), true),
                      std::move(all_rows),
                      {},
                      {},
                      {}};
  return run_loop(in);
}

namespace identify_loop {

IdentifyResult run_loop(const LoopInputs& in) {
  const auto start_time = std::chrono::steady_clock::now();
  const QuietSolverWarnings quiet;
  IdentifyResult result;

  CaseNominal case_nominal;
  fit_case_nominal(in, case_nominal);
  Discretisation chosen;
  choose_discretisation(in, case_nominal, result, chosen);
  const Setup& setup = loop_setup(case_nominal, chosen);
  result.warnings = case_nominal.setup.warnings;
  if (&setup != &case_nominal.setup)
    for (const std::string& w : setup.warnings) result.warnings.push_back("refined level: " + w);
  // The loop factorises models of a few thousand DOFs many times: one thread. CHOLMOD's OpenMP
  // workers gain little at this size and spin between calls (measured: 22 % of the CPU time of
  // a 3D run went to spinning workers on a loaded 2-core machine).
  const analysis::ThreadScope single_thread(1);
  Nominal nominal;
  fit_nominal(in, case_nominal, chosen, result, nominal);
  Candidates candidates;
  collect_candidates(in, setup, nominal, result, candidates);

  Selection selection;
  const SelectionInputs selection_inputs{in, setup, nominal, candidates};
  select_forward(selection_inputs, result, selection);
  swap_effects(selection_inputs, result, selection);

  FinalFit final_fit;
  fit_final(in, setup, case_nominal, nominal, result, selection, final_fit);
  report_final(in, case_nominal, chosen, nominal, selection, final_fit, result);
  run_holdout(in, setup, nominal, selection, result);

  // Last: the refined setup points into the refined problem until here.
  if (chosen.refined_problem)
    result.discretization.chosen_problem = std::move(chosen.refined_problem);
  result.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count();
  return result;
}

}  // namespace identify_loop

std::vector<Eigen::Vector3d> simulate_markers(
    const analysis::Problem& problem, const std::vector<Marker>& markers,
    const std::vector<MarkerPlacement>& placements,
    const std::vector<std::pair<std::string, Eigen::VectorXd>>& effects) {
  using namespace identify_loop;
  Setup setup;
  make_setup(setup, problem, markers, placements, false, {});
  return simulate_with_effects(setup, markers.size(), effects, "simulate_markers");
}

}  // namespace isospring::fitting
