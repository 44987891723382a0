// The hold-out stage of the measured-data loop (loop_state.hpp): independent refits of the
// nominal and the final model on part of the data, validated on the rest.
#include <Eigen/QR>
#include <algorithm>
#include <exception>
#include <memory>
#include <mutex>
#include <new>
#include <optional>
#include <stdexcept>

#include "identify/loop_state.hpp"

namespace isospring::fitting::identify_loop {

namespace {

// What every fold reads: the loop's setup, the nominal and the final model's starting values,
// the noise level of the final weights.
struct Folds {
  const LoopInputs& in;
  const Setup& setup;
  const Nominal& nominal;
  const Selection& selection;
  double noise = 0.0;
  // One factorisation cache per fold.
  std::vector<std::shared_ptr<FactorizationCache>> caches;
};

// A fold's refit. Its large-deformation Jacobians solve on the tangent at hand (fold_cache); a
// refit that fails that way is repeated with exact ones, as the folds refitted before.
Fit fold_fit(const Setup& setup, const Model& model, const std::vector<Eigen::VectorXd>& weights,
             FactorizationCache& cache) {
  const Fit fit = run_fit(setup, model, weights);
  if (fit.ok || !cache.jacobians_on_kept_tangents || !model.forward->nonlinear()) return fit;
  cache.jacobians_on_kept_tangents = false;
  return run_fit(setup, model, weights);
}

// Fold 0: fit on the even markers of every load case, validate on the odd ones.
std::optional<HoldoutCheck> markers_fold(const Folds& folds) {
  const Setup& setup = folds.setup;
  const std::vector<Marker>& markers = folds.in.markers;
  std::vector<bool> fit_marker(markers.size(), false);
  std::vector<int> validation;
  for (const auto& ids : setup.markers)
    for (size_t k = 0; k < ids.size(); ++k) {
      if (k % 2 == 0)
        fit_marker[static_cast<size_t>(ids[k])] = true;
      else
        validation.push_back(ids[k]);
    }
  const auto holdout_weights = make_weights(setup, folds.noise, fit_marker);
  const auto& cache = folds.caches[0];
  if (validation.empty()) return std::nullopt;
  HoldoutCheck check;
  check.fit_markers = static_cast<int>(markers.size() - validation.size());
  check.validation_markers = static_cast<int>(validation.size());
  // The final model first: the fold's cache starts with the loop's last factorisation, which is
  // usually the final model's (the nominal model's only when they share their stiffness).
  const bool with_effects = !folds.selection.chosen.empty();
  if (with_effects) {
    const Model full =
        build_model(setup, folds.selection.chosen, folds.selection.current_fit.theta, cache);
    const Fit full_fit = fold_fit(setup, full, holdout_weights, *cache);
    if (!full_fit.ok) return std::nullopt;
    check.validation_after =
        summarize(marker_misfit(setup, full, full_fit.theta, markers), validation, setup.dim);
  }
  const Model base = build_model(setup, {}, folds.nominal.fit.theta, cache);
  const Fit base_fit = run_fit(setup, base, holdout_weights);
  if (!base_fit.ok) return std::nullopt;
  check.validation_before =
      summarize(marker_misfit(setup, base, base_fit.theta, markers), validation, setup.dim);
  // Without effects the final model is the nominal one: same model, same weights, same fit.
  if (!with_effects) check.validation_after = check.validation_before;
  return check;
}

// The residual of load case l at the fit, less what the parameters acting on load case l alone
// (columns that vanish on every other load case) can still take up: those were not fitted to
// it, so they get their least-squares step here. Writes the number of such parameters.
Eigen::VectorXd case_residual(const Setup& setup, size_t l, const ModelEvaluation& eval,
                              const Eigen::VectorXd& theta, int& local_parameters) {
  const int dim = setup.dim;
  std::vector<Eigen::Index> local;
  for (Eigen::Index k = 0; k < theta.size(); ++k) {
    double elsewhere = 0.0;
    for (size_t o = 0; o < eval.jacobians.size(); ++o)
      if (o != l) elsewhere += eval.jacobians[o].col(k).squaredNorm();
    if (elsewhere == 0.0 && eval.jacobians[l].col(k).squaredNorm() > 0.0) local.push_back(k);
  }
  local_parameters = static_cast<int>(local.size());
  Eigen::VectorXd r = setup.measured[l] - eval.predictions[l];
  if (local.empty()) return r;
  Eigen::MatrixXd j(r.size(), static_cast<Eigen::Index>(local.size()));
  for (size_t k = 0; k < local.size(); ++k)
    j.col(static_cast<Eigen::Index>(k)) = eval.jacobians[l].col(local[k]);
  // Weighted like the fit (component weights), so the step is the least-squares one.
  Eigen::VectorXd rw = r;
  for (Eigen::Index k = 0; k < r.size(); ++k) {
    const double s = setup.component_weight[k % dim];
    rw[k] *= s;
    j.row(k) *= s;
  }
  const Eigen::VectorXd step = j.colPivHouseholderQr().solve(rw);
  for (size_t k = 0; k < local.size(); ++k)
    r -= step[static_cast<Eigen::Index>(k)] * eval.jacobians[l].col(local[k]);
  return r;
}

// Fold l + 1: leave load case l out. Do the effects predict a load case they were not fitted to?
std::optional<LoadCaseHoldout> case_fold(const Folds& folds, size_t l) {
  const Setup& setup = folds.setup;
  const std::vector<Marker>& markers = folds.in.markers;
  const int dim = setup.dim;
  std::vector<bool> fit_marker(markers.size(), true);
  for (int m : setup.markers[l]) fit_marker[static_cast<size_t>(m)] = false;
  const auto w = make_weights(setup, folds.noise, fit_marker);
  const auto& cache = folds.caches[l + 1];
  LoadCaseHoldout out;
  out.id = folds.in.problem.load_cases[l].id;
  out.markers = static_cast<int>(setup.markers[l].size());
  // The final model first (as in markers_fold); without effects it is the nominal one: same
  // model, same weights, same fit.
  const bool with_effects = !folds.selection.chosen.empty();
  for (const bool final_model : {true, false}) {
    if (final_model && !with_effects) continue;
    const Model model = final_model ? build_model(setup, folds.selection.chosen,
                                                  folds.selection.current_fit.theta, cache)
                                    : build_model(setup, {}, folds.nominal.fit.theta, cache);
    const Fit fit = fold_fit(setup, model, w, *cache);
    if (!fit.ok) return std::nullopt;
    const ModelEvaluation eval = model.forward->evaluate(fit.theta, true);
    int local_parameters = 0;
    const Eigen::VectorXd r = case_residual(setup, l, eval, fit.theta, local_parameters);
    std::vector<Eigen::Vector3d> residual(markers.size(), Eigen::Vector3d::Zero());
    for (size_t k = 0; k < setup.markers[l].size(); ++k)
      for (int c = 0; c < dim; ++c)
        residual[static_cast<size_t>(setup.markers[l][k])][c] =
            r[static_cast<Eigen::Index>(k) * dim + c];
    (final_model ? out.after : out.before) = summarize(residual, setup.markers[l], dim);
    if (final_model) out.local_parameters = local_parameters;
  }
  if (!with_effects) out.after = out.before;
  return out;
}

}  // namespace

// The loop's cache holding the factor of the final model's K at its fitted parameters, which
// every fold copies: each fold refits the final model from those parameters, so its first
// evaluation solves without factorising, and a refit from there usually takes 1-3 steps under
// the fold's weights. Usually the cache holds that factor already (the final fit's covariance
// was the last evaluation) and this costs one solve per load case with it.
void factor_final_model(const Selection& selection) {
  if (!selection.current.forward || selection.current.forward->nonlinear()) return;
  try {
    (void)selection.current.forward->evaluate(selection.current_fit.theta, false);
  } catch (const std::runtime_error&) {
    // Not positive definite at the fit (cannot happen for a fit that ended there): the folds
    // factorise on their own, as they would without the copy.
  }
}

// A fold's cache starts with the loop's large-deformation solutions (Newton's starts) and its
// latest kept tangent per load case, the final model's at its fit: a fold's refit starts there,
// so its first Jacobian solves on it without a tangent of its own, and its first trial step
// takes its chord steps on it (KeptTangent). The same factors, not copies: their solves take
// turns, and a copy per fold would hold one more factor per load case in memory.
std::shared_ptr<FactorizationCache> fold_cache(FactorizationCache& loop) {
  auto cache = make_factorization_cache();
  const std::lock_guard<std::mutex> lock(loop.nonlinear_mutex);
  cache->nonlinear_starts = loop.nonlinear_starts;
  cache->linear_starts = loop.linear_starts;
  cache->jacobians_on_kept_tangents = true;
  cache->tangents.resize(loop.tangents.size());
  for (size_t l = 0; l < loop.tangents.size(); ++l)
    if (!loop.tangents[l].empty()) cache->tangents[l] = {loop.tangents[l].front()};
  return cache;
}

namespace {

// The loop's models are done when the folds start: of its kept tangents only the latest per load
// case serve them (fold_cache), and the older ones are freed before the folds factorise their
// own (each a factor per load case, two folds at a time).
void free_older_tangents(FactorizationCache& loop) {
  const std::lock_guard<std::mutex> lock(loop.nonlinear_mutex);
  for (auto& kept : loop.tangents)
    if (kept.size() > 1) kept.resize(1);
}

}  // namespace

// Stage 9: hold-out folds, independent refits: fit on the even markers of every load case and
// validate on the odd ones (fold 0), and leave one load case out (folds 1..). They run on the
// machine's cores, each with a factorisation cache of its own (they differ in their weights, so
// one shared cache would serialise them and factorise at every switch). Measured on the suite's
// tube_graded (5,832 DOFs, a factorisation per evaluation): 19 s one after the other. Each
// fold's cache starts as a copy of the loop's factorisation: the folds' fits start at the loop's
// fit, where K is the loop's (up to the scale of E), so a fold whose model has no stiffness
// parameter beyond E factorises nothing.
void run_holdout(const LoopInputs& in, const Setup& setup, const Nominal& nominal,
                 const Selection& selection, IdentifyResult& result) {
  const size_t num_cases = in.problem.load_cases.size();
  const bool leave_cases_out = in.options.holdout && num_cases >= 2;
  const int folds =
      in.options.holdout ? 1 + (leave_cases_out ? static_cast<int>(num_cases) : 0) : 0;
  Folds fold_inputs{in, setup, nominal, selection, result.noise_estimate, {}};
  if (folds > 0) free_older_tangents(*setup.factorizations);
  for (int f = 0; f < folds; ++f) fold_inputs.caches.push_back(fold_cache(*setup.factorizations));
  if (folds > 0 && !selection.chosen.empty()) factor_final_model(selection);
  std::optional<HoldoutCheck> marker_check;
  std::vector<std::optional<LoadCaseHoldout>> case_folds(num_cases);
  std::vector<std::exception_ptr> fold_errors(static_cast<size_t>(folds));
  // What the folds' large-deformation refits cost, for the progress line that profiles read.
  std::vector<long> tangents_factorised(static_cast<size_t>(folds), 0);
  std::vector<long> kept_reused(static_cast<size_t>(folds), 0);
  std::vector<long> on_kept(static_cast<size_t>(folds), 0);
  if (folds > 0)
    in.say(
        "hold-out checks (" + std::to_string(folds) + " refits of " +
        (selection.chosen.empty() ? "the nominal model, which is the final one)" : "two models)"));
    // Nested OpenMP is off: the folds' own solves run on one thread each, as in the loop.
#pragma omp parallel for schedule(dynamic) \
    num_threads(std::max(1, std::min(in.element_threads, folds)))
  for (int f = 0; f < folds; ++f) {
    try {
      try {  // the loop's last factorisation, copied when the fold starts (one per thread alive)
        const std::lock_guard<std::mutex> lock(setup.factorizations->mutex);
        fold_inputs.caches[static_cast<size_t>(f)]->copy_factorization(*setup.factorizations);
      } catch (const std::bad_alloc&) {
        // No memory for a copy: the fold factorises on its own, as it would without one.
      }
      if (f == 0)
        marker_check = markers_fold(fold_inputs);
      else
        case_folds[static_cast<size_t>(f - 1)] = case_fold(fold_inputs, static_cast<size_t>(f - 1));
      const FactorizationCache& cache = *fold_inputs.caches[static_cast<size_t>(f)];
      tangents_factorised[static_cast<size_t>(f)] = cache.tangent_factorizations;
      kept_reused[static_cast<size_t>(f)] = cache.kept_state_reuses;
      on_kept[static_cast<size_t>(f)] = cache.jacobians_on_kept_tangent;
      fold_inputs.caches[static_cast<size_t>(f)].reset();  // its models are gone: free the factor
    } catch (...) {
      fold_errors[static_cast<size_t>(f)] = std::current_exception();
    }
  }
  for (const auto& error : fold_errors)
    if (error) std::rethrow_exception(error);
  long factorised = 0, reused = 0, approximate = 0;
  for (int f = 0; f < folds; ++f) {
    factorised += tangents_factorised[static_cast<size_t>(f)];
    reused += kept_reused[static_cast<size_t>(f)];
    approximate += on_kept[static_cast<size_t>(f)];
  }
  if (factorised + reused + approximate > 0)
    in.say("hold-out refits: " + std::to_string(factorised) +
           " large-deformation tangents factorised; load-case Jacobians on a kept tangent: " +
           std::to_string(reused) + " at its own state, " + std::to_string(approximate) +
           " at a nearby one");
  if (marker_check) {
    result.holdout = *marker_check;
    result.holdout_done = true;
  }
  for (const auto& fold : case_folds)
    if (fold) result.load_case_holdout.push_back(*fold);
}

}  // namespace isospring::fitting::identify_loop
