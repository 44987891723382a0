// The last fits of the measured-data loop and their report (loop_state.hpp): the noise level
// re-estimated from the final residual, the nominal and the selected model under its weights
// with their covariances, the parameters and the residual summaries.
#include <cmath>
#include <memory>
#include <optional>

#include "identify/loop_state.hpp"

namespace isospring::fitting::identify_loop {

namespace {

// The nominal model's parameters under the final weights, for the report's "before" column;
// its weighted RSS. The nominal fit itself when the weights only rescale its own.
double report_nominal_under(const LoopInputs& in, const Setup& setup,
                            const CaseNominal& case_nominal, const Nominal& nominal,
                            const std::vector<Eigen::VectorXd>& weights, IdentifyResult& result) {
  Eigen::MatrixXd cov_before;
  const Model nominal_model = build_model(setup, {}, nominal.fit.theta);
  const std::optional<Fit> nominal_reweighted = reweighted(
      nominal.fit, make_weights(setup, case_nominal.provisional, in.all_markers), weights);
  const Fit baseline_final =
      nominal_reweighted ? *nominal_reweighted : run_fit(setup, nominal_model, weights);
  if (baseline_final.ok) cov_before = fit_covariance(nominal_model, baseline_final.theta, weights);
  if (baseline_final.ok) {
    const double e_prior = in.problem.material.youngs_modulus;
    const Eigen::VectorXd& t = baseline_final.theta;
    result.parameters_before.push_back(
        {"material", "E", "Pa", e_prior * t[0], e_prior * std::sqrt(cov_before(0, 0))});
    if (in.options.fit_poisson)
      result.parameters_before.push_back(
          {"material", "nu", "1", t[1], std::sqrt(cov_before(1, 1))});
  }
  return baseline_final.rss;
}

// The material's and every added effect's parameters with their standard errors, the derived
// values and the notes of what recalibrate_identified does with them.
void report_parameters(const LoopInputs& in, const Selection& selection, const Eigen::MatrixXd& cov,
                       IdentifyResult& result) {
  const Eigen::VectorXd& theta = selection.current_fit.theta;
  auto se = [&](int k) { return std::sqrt(cov(k, k)); };
  const double e_prior = in.problem.material.youngs_modulus;
  result.parameters.push_back({"material", "E", "Pa", e_prior * theta[0], e_prior * se(0)});
  result.youngs_modulus = e_prior * theta[0];
  result.poisson_ratio = in.problem.material.poisson_ratio;
  if (in.options.fit_poisson) {
    result.parameters.push_back({"material", "nu", "1", theta[1], se(1)});
    result.poisson_ratio = theta[1];
  }
  const std::vector<const Effect*>& chosen = selection.chosen;
  for (size_t e = 0; e < chosen.size(); ++e) {
    const auto [first, count] = selection.current.blocks[e];
    const auto names_e = chosen[e]->parameter_names();
    const auto units_e = chosen[e]->parameter_units();
    for (int k = 0; k < count; ++k)
      result.parameters.push_back({chosen[e]->name(), names_e[static_cast<size_t>(k)],
                                   units_e[static_cast<size_t>(k)], theta[first + k],
                                   se(first + k)});
    for (const auto& d : chosen[e]->derived(theta.segment(first, count)))
      result.derived.emplace_back(chosen[e]->name() + "." + d.first, d.second);
    result.effects_added.push_back(chosen[e]->name());
    result.effect_values.emplace_back(chosen[e]->name(), theta.segment(first, count));
    // The note of what recalibrate_identified does with these values (the same function), on a
    // scratch copy of the changes: identify itself changes nothing.
    SpringModelChanges scratch;
    result.spring_model_notes.push_back(
        carry_over(chosen[e]->name(), theta.segment(first, count), scratch));
  }
}

// The corrected reference on the case's own DOFs (the spring model's net) when the loop ran on
// a refined level: the same effects built on the case's discretisation, evaluated at the
// identified parameters.
std::vector<Eigen::VectorXd> corrected_on_case(const Setup& case_setup,
                                               const std::vector<const Effect*>& chosen,
                                               const Eigen::VectorXd& theta) {
  std::vector<std::unique_ptr<Effect>> case_effects;
  std::vector<const Effect*> on_case;
  for (const Effect* effect : chosen) {
    std::string why;
    case_effects.push_back(make_effect(effect->name(), case_setup.context, &why));
    if (!case_effects.back())
      throw std::runtime_error("effect " + effect->name() +
                               " does not apply to the case's discretisation: " + why);
    on_case.push_back(case_effects.back().get());
  }
  const Model case_model = build_model(case_setup, on_case, theta);
  if (case_model.forward->num_parameters() != theta.size())
    throw std::runtime_error("the effects have other parameters on the case's discretisation");
  return case_model.forward->evaluate(theta, false).displacements;
}

}  // namespace

// Stage 7. Without a given noise level, it is re-estimated from the final residual: the baseline
// residual's smooth misfit leaks into neighbour differences when markers are coarse. The
// selection's fits were made under the weights of the first noise estimate; the re-estimate
// rescales them, which leaves the optimum where it is.
void fit_final(const LoopInputs& in, const Setup& setup, const CaseNominal& case_nominal,
               const Nominal& nominal, IdentifyResult& result, Selection& selection,
               FinalFit& out) {
  if (!result.noise_given) {
    const std::vector<Eigen::Vector3d> residual =
        marker_misfit(setup, selection.current, selection.current_fit.theta, in.markers);
    const double sigma =
        weighted_noise(setup, nominal.residual.positions, residual, nominal.residual.group);
    if (sigma > 0.0) result.noise_estimate = sigma;
  }
  out.weights = make_weights(setup, result.noise_estimate, in.all_markers);
  out.rss_before = report_nominal_under(in, setup, case_nominal, nominal, out.weights, result);
  // The final fit with covariance.
  Fit& current_fit = selection.current_fit;
  if (const std::optional<Fit> same = reweighted(current_fit, nominal.weights, out.weights)) {
    current_fit = *same;
    out.covariance = fit_covariance(selection.current, current_fit.theta, out.weights);
  } else {
    current_fit = run_fit(setup, selection.current, out.weights, &out.covariance);
  }
  if (!current_fit.ok) throw std::runtime_error("the final fit failed: " + current_fit.message);
}

// Stage 8: the final model's parameters, predictions and residual summaries.
void report_final(const LoopInputs& in, const CaseNominal& case_nominal,
                  const Discretisation& chosen, const Nominal& nominal, const Selection& selection,
                  const FinalFit& final_fit, IdentifyResult& result) {
  const Setup& setup = loop_setup(case_nominal, chosen);
  const int dim = setup.dim;
  const Fit& current_fit = selection.current_fit;
  const Eigen::VectorXd& theta = current_fit.theta;
  report_parameters(in, selection, final_fit.covariance, result);
  for (int c = 0; c < dim; ++c) result.component_weights.push_back(setup.component_weight[c]);
  result.model_after = marker_predictions(setup, selection.current, theta, in.markers.size());
  result.corrected_displacements = selection.current.forward->evaluate(theta, false).displacements;
  if (chosen.refined_setup)
    result.corrected_displacements = corrected_on_case(case_nominal.setup, selection.chosen, theta);
  std::vector<Eigen::Vector3d> residual_after(in.markers.size());
  for (size_t m = 0; m < in.markers.size(); ++m)
    residual_after[m] = in.markers[m].displacement - result.model_after[m];
  result.after = summarize(residual_after, in.all_rows, dim);
  result.residual_after = describe(setup, nominal, residual_after);
  result.observations = current_fit.rows;
  // Chi-square per degree of freedom against the noise level (weights are 1/sigma).
  result.chi2_before = final_fit.rss_before / std::max(1, current_fit.rows - selection.p_before);
  result.chi2_after =
      current_fit.rss / std::max(1, current_fit.rows - static_cast<int>(theta.size()));
  for (size_t l = 0; l < in.problem.load_cases.size(); ++l) {
    LoadCaseErrors errors;
    errors.id = in.problem.load_cases[l].id;
    errors.markers = static_cast<int>(setup.markers[l].size());
    errors.before = summarize(nominal.residual.residual, setup.markers[l], dim);
    errors.after = summarize(residual_after, setup.markers[l], dim);
    result.load_cases.push_back(errors);
  }
}

}  // namespace isospring::fitting::identify_loop
