// `calibrate` with a finite-strain material.model: fitting::calibrate_large_deformation on the
// case's fitted load cases, its held-out cases against their finite-strain references, and the
// result in the shape of the linear calibration's (CalibrationResult) so that every output of
// the command is written the same way (see calibrate_command.hpp).
#include "calibrate_large_deformation.hpp"

#include <algorithm>
#include <cmath>

#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/sides.hpp"
#include "isospring/analysis/spring_mechanics.hpp"
#include "isospring/fitting/error_metrics.hpp"
#include "isospring/fitting/large_deformation_calibration.hpp"
#include "isospring/io/report_case.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::workflows {
namespace {

using Controls = std::vector<std::vector<Eigen::Vector3d>>;  // [patch][control point]

std::string law_name(analysis::HyperelasticMaterial law) {
  return law == analysis::HyperelasticMaterial::kNeoHookean ? "neo_hookean" : "svk";
}

// Combinations the large-deformation calibration does not offer, each refused by the field.
void refuse_unsupported(const io::Case& c, const io::CalibrationRequest& request) {
  const std::string where = c.file.filename().string() + ": calibration.";
  const std::string why =
      " with a finite-strain material.model (the large-deformation calibration fits grouped "
      "stiffnesses to finite-strain references by the springs' nonlinear equilibrium)";
  if (request.amplitudes.empty())
    throw nurbs::InputError(
        where + "amplitudes: material.model \"" + law_name(*c.nonlinear_material) +
        "\" calibrates at large deformation and needs the amplitudes to fit at: a list of "
        "%eps_G in percent, e.g. \"amplitudes\": [5, 20], or {\"max\": 20, \"steps\": 4} (or set "
        "material.model to \"linear\")");
  if (request.generalisation)
    throw nurbs::InputError(where + "generalisation: not available" + why +
                            "; remove it and give fit_load_cases / holdout_load_cases");
  if (request.settings.per_spring)
    throw nurbs::InputError(where + "grouping.per_spring: not available" + why);
  if (request.settings.max_step_us > 0.0)
    throw nurbs::InputError(where + "max_step_us: not available" + why +
                            "; choose the model kind with volume_terms / shear_terms");
  if (request.matrix_approach_given && request.matrix_approach)
    throw nurbs::InputError(where + "matrix_approach: not available" + why + "; remove it");
  if (request.acceleration_objective_given && request.acceleration_objective)
    throw nurbs::InputError(where + "acceleration_objective: not available" + why + "; remove it");
}

// The case's held-out load cases (calibration.holdout_load_cases), as given; every named case
// must exist.
analysis::Problem held_out_problem(const analysis::Problem& problem,
                                   const fitting::CalibrationSettings& settings) {
  for (const auto& id : settings.fit_cases)
    if (std::none_of(problem.load_cases.begin(), problem.load_cases.end(),
                     [&](const auto& lc) { return lc.id == id; }))
      throw nurbs::InputError("calibration.fit_load_cases: no load case '" + id +
                              "' in the case file");
  analysis::Problem held = problem;
  held.load_cases.clear();
  for (const auto& id : settings.holdout_cases) {
    const auto it = std::find_if(problem.load_cases.begin(), problem.load_cases.end(),
                                 [&](const auto& lc) { return lc.id == id; });
    if (it == problem.load_cases.end())
      throw nurbs::InputError("calibration.holdout_load_cases: no load case '" + id +
                              "' in the case file");
    held.load_cases.push_back(*it);
  }
  return held;
}

// One evaluated case as the linear calibration reports it: control, field and surface metrics
// of the model's nonlinear equilibrium against the finite-strain reference.
fitting::CaseErrors case_errors(const analysis::Problem& problem, const analysis::DofMap& dofs,
                                const fitting::LargeDeformationCase& evaluated,
                                const Controls& reference, int samples) {
  fitting::CaseErrors e;
  e.id = evaluated.id;
  e.control = evaluated.control;
  e.node_error = evaluated.node_error;
  Controls model = reference;
  for (size_t p = 0; p < model.size(); ++p)
    for (size_t i = 0; i < model[p].size(); ++i)
      model[p][i] +=
          e.node_error[static_cast<size_t>(dofs.node(static_cast<int>(p), static_cast<int>(i)))];
  e.field = fitting::field_error_metrics(problem.patches, reference, model, samples);
  e.surface = fitting::surface_error_metrics(problem.patches, reference, model, samples,
                                             analysis::inner_sides(problem.patches, dofs));
  return e;
}

// Per amplitude: the fitted cases' worst and root-mean-square %e_rms, the references' mean
// %eps_G and the worst of the linear start (its nonlinear equilibrium on the same cases).
std::vector<LargeDeformationAmplitude> amplitude_rows(
    const std::vector<double>& amplitudes, double reached,
    const std::vector<fitting::LargeDeformationCase>& fitted,
    const std::vector<fitting::LargeDeformationCase>& start) {
  std::vector<LargeDeformationAmplitude> rows;
  const size_t reached_count = static_cast<size_t>(
      std::find(amplitudes.begin(), amplitudes.end(), reached) - amplitudes.begin() + 1);
  const size_t per = fitted.size() / std::max<size_t>(reached_count, 1);
  for (size_t k = 0; k < reached_count; ++k) {
    LargeDeformationAmplitude row;
    row.amplitude = amplitudes[k];
    double sum = 0.0, eps = 0.0;
    for (size_t c = k * per; c < (k + 1) * per; ++c) {
      row.worst_percent_e_rms = std::max(row.worst_percent_e_rms, fitted[c].control.percent_e_rms);
      sum += fitted[c].control.percent_e_rms * fitted[c].control.percent_e_rms;
      eps += fitted[c].percent_eps_g;
      if (start[c].solved)
        row.start_worst_percent_e_rms =
            std::max(row.start_worst_percent_e_rms, start[c].control.percent_e_rms);
      else
        ++row.start_without_equilibrium;
      ++row.cases;
    }
    row.percent_e_rms = std::sqrt(sum / std::max(row.cases, 1));
    row.reference_percent_eps_g = eps / std::max(row.cases, 1);
    rows.push_back(row);
  }
  return rows;
}

// The held-out cases' finite-strain references (DofMap vectors), their control displacements
// appended to `summary`'s viewer references.
std::vector<Eigen::VectorXd> held_out_references(const analysis::Problem& held,
                                                 analysis::HyperelasticMaterial law,
                                                 LargeDeformationSummary& summary,
                                                 const io::Progress& progress) {
  std::vector<Eigen::VectorXd> references;
  if (held.load_cases.empty()) return references;
  progress("finite-strain IGA references of the " + std::to_string(held.load_cases.size()) +
           " held-out load cases");
  analysis::NonlinearOptions options;
  options.material = law;
  for (auto& r : analysis::solve_static_nonlinear(held, options)) {
    references.push_back(r.displacement);
    summary.reference_controls.push_back(r.control_displacements);
  }
  return references;
}

}  // namespace

CalibrateCommandResult run_calibrate_large_deformation(io::Case c, io::CalibrationRequest request,
                                                       const io::Progress& progress) {
  refuse_unsupported(c, request);
  fitting::CalibrationSettings& settings = request.settings;
  settings.matrix_approach = false;
  request.matrix_approach = false;
  request.acceleration_objective = false;
  if (!progress.quiet()) {
    settings.progress = [&progress](const std::string& line) { progress(line); };
    settings.iteration = [&progress](const std::string& stage, int iteration, double cost) {
      progress.update(stage, iteration, cost);
    };
  }
  fitting::LargeDeformationSettings large;
  large.law = *c.nonlinear_material;
  large.amplitudes = request.amplitudes;
  const analysis::Problem held = held_out_problem(c.problem, settings);
  fitting::LargeDeformationResult fit =
      fitting::calibrate_large_deformation(c.problem, settings, large);

  // The problem of the outputs: the fitted cases as scaled, then the held-out cases as given.
  analysis::Problem problem = c.problem;
  problem.load_cases = fit.scaled_cases;
  for (const auto& lc : held.load_cases) problem.load_cases.push_back(lc);
  const analysis::DofMap dofs(problem);
  auto& network = fit.model.network;
  if (settings.damping_alpha > 0.0) analysis::assign_damping_alpha(network, settings.damping_alpha);
  if (settings.damping_ratio > 0.0) analysis::assign_damping_ratio(network, settings.damping_ratio);

  LargeDeformationSummary summary;
  summary.law = law_name(large.law);
  summary.amplitudes = large.amplitudes;
  summary.reached_amplitude = fit.reached_amplitude;
  summary.stopped = fit.stopped;
  for (const auto& r : fit.references)
    summary.reference_controls.push_back(r.control_displacements);
  const std::vector<Eigen::VectorXd> held_references =
      held_out_references(held, large.law, summary, progress);
  // The linear start's nonlinear equilibrium on the fitted cases: what the nonlinear fit buys.
  analysis::Problem scaled = c.problem;
  scaled.load_cases = fit.scaled_cases;
  std::vector<Eigen::VectorXd> fitted_references;
  for (const auto& r : fit.references) fitted_references.push_back(r.displacement);
  const std::vector<fitting::LargeDeformationCase> start = fitting::evaluate_large_deformation(
      scaled, fitting::spring_model_of(scaled, fit.start), fitted_references);
  summary.rows = amplitude_rows(large.amplitudes, fit.reached_amplitude, fit.fitted, start);

  fitting::CalibrationResult result;
  result.mesh = fit.start.mesh;
  result.mesh.network = network;
  result.grouping = fit.start.grouping;
  result.gamma = fit.start.gamma;
  result.parameters = fit.start.parameters;
  result.fit_result = fit.fit;
  result.reference_seconds = fit.reference_seconds;
  result.fit_seconds = fit.fit_seconds;
  result.sweep = fit.start.sweep;
  if (!fit.stopped.empty()) result.warnings.push_back(fit.stopped);
  const size_t n_fitted = fit.scaled_cases.size();
  for (size_t k = 0; k < n_fitted; ++k)
    if (fit.fitted[k].solved)  // always, under the continuation's rule; guarded all the same
      result.fit.push_back(case_errors(problem, dofs, fit.fitted[k], summary.reference_controls[k],
                                       settings.field_samples));
  const std::vector<fitting::LargeDeformationCase> evaluated =
      fitting::evaluate_large_deformation(held, fit.model, held_references);
  for (size_t k = 0; k < evaluated.size(); ++k) {
    if (!evaluated[k].solved) {
      summary.holdout_without_equilibrium.push_back(evaluated[k].id);
      result.warnings.push_back("held-out load case " + evaluated[k].id +
                                ": the calibrated spring model finds no equilibrium under it");
      continue;
    }
    result.holdout.push_back(case_errors(problem, dofs, evaluated[k],
                                         summary.reference_controls[n_fitted + k],
                                         settings.field_samples));
  }
  result.particle_loads = fitting::particle_loads(problem, fit.model);
  for (const auto& lc : problem.load_cases) result.load_ids.push_back(lc.id);

  double worst_fitted = 0.0, worst_holdout = 0.0;
  for (const auto& e : result.fit) worst_fitted = std::max(worst_fitted, e.control.percent_e_rms);
  for (const auto& e : result.holdout)
    worst_holdout = std::max(worst_holdout, e.control.percent_e_rms);
  const double worst = std::max(worst_fitted, worst_holdout);
  if (request.target_percent_e_rms > 0.0 && worst > request.target_percent_e_rms)
    result.warnings.push_back("the worst %e_rms over fitted and held-out load cases (" +
                              io::format_number(worst, 3) + ") exceeds target_percent_e_rms " +
                              io::format_number(request.target_percent_e_rms, 3));
  for (const auto& warning : result.mesh.warnings) progress.warn(warning);
  for (const auto& warning : result.warnings) progress.warn(warning);

  CalibrateCommandResult r;
  r.input = c.file;
  r.case_name = c.name;
  r.case_summary = io::case_summary(c, c.problem);
  settings.progress = nullptr;
  settings.iteration = nullptr;
  r.request = std::move(request);
  r.calibration = std::move(result);
  r.worst_fitted = worst_fitted;
  r.worst_holdout = worst_holdout;
  r.worst = worst;
  r.problem = std::move(problem);
  r.large_deformation = std::move(summary);
  return r;
}

}  // namespace isospring::workflows
