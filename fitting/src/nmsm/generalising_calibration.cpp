// Cross-validated choice of the spring model's freedom (header: procedure and why).
// calibrate_for_generalisation() lists the stages: the training cases, one shared IGA reference,
// every model kind's candidates scored over the folds, the best candidate refitted.
#include "isospring/fitting/generalising_calibration.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "isospring/analysis/static_solver.hpp"
#include "isospring/fitting/step_cost.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::fitting {

namespace {

std::string format(const char* pattern, double a, double b) {
  char text[200];
  std::snprintf(text, sizeof text, pattern, a, b);
  return text;
}

double worst_of(const std::vector<CaseErrors>& cases) {
  double worst = 0.0;
  for (const auto& c : cases) worst = std::max(worst, c.control.percent_e_rms);
  return worst;
}

// Stage: the training cases (settings.fit_cases, or every case not held out), after checking
// the options that do not need the problem solved.
std::vector<std::string> training_cases(const analysis::Problem& problem,
                                        const CalibrationSettings& settings,
                                        const GeneralisationOptions& options) {
  if (options.gammas.empty())
    throw nurbs::InputError("generalisation: give at least one gamma candidate");
  for (double w : options.prior_weights)
    if (!(w > 0.0)) throw nurbs::InputError("generalisation: prior weights must be positive");
  std::vector<std::string> training = settings.fit_cases;
  if (training.empty())
    for (const auto& lc : problem.load_cases)
      if (std::find(settings.holdout_cases.begin(), settings.holdout_cases.end(), lc.id) ==
          settings.holdout_cases.end())
        training.push_back(lc.id);
  if (options.folds < 2 || options.folds > static_cast<int>(training.size()))
    throw nurbs::InputError(
        "generalisation: folds must be between 2 and the number of training "
        "cases (" +
        std::to_string(training.size()) + ")");
  return training;
}

// Stage: the settings every fit below starts from: the caller's, with one IGA reference for all
// of them and a plain grouped fit (the candidates set the grouping).
CalibrationSettings shared_settings(const analysis::Problem& problem,
                                    const CalibrationSettings& settings) {
  CalibrationSettings base = settings;
  if (base.reference_displacements.empty()) {
    if (settings.progress) settings.progress("IGA reference: solving the load cases");
    for (auto& lc : analysis::solve_static(problem).load_cases)
      base.reference_displacements.push_back(std::move(lc.displacement));
  }
  base.gamma_sweep.clear();
  base.per_spring = false;
  base.per_spring_start.clear();
  base.regularization = 0.0;
  base.prior_weight = 0.0;
  base.matrix_approach = false;
  // [S15 4.19]'s upper bounds per group: fitted to several loads, a group of the curved
  // membranes (flattened corner cells of the single-patch disk) otherwise runs off towards
  // infinite stiffness, and the network's K turns numerically singular (pivots below 1e-13 of
  // the largest).
  base.upper_bounds = true;
  return base;
}

void check_model_kinds(const GeneralisationOptions& options) {
  if (options.volume_terms.empty() || options.shear_terms.empty() || options.strain_points.empty())
    throw nurbs::InputError(
        "generalisation: give at least one model kind (volume_terms, shear_terms, "
        "strain_points)");
  for (int n : options.strain_points)
    if (n < 0 || n > 4)
      throw nurbs::InputError("generalisation: strain_points entries must be 0 .. 4");
}

// The training cases dealt into folds, and the score of a candidate over them.
struct CrossValidation {
  const analysis::Problem& problem;
  const CalibrationSettings& settings;  // the caller's (its progress)
  const std::vector<std::string>& training;
  int folds;

  // Fold f: fit on the training cases outside it, measure the ones inside it.
  CalibrationSettings fold_settings(const CalibrationSettings& base, int f) const {
    CalibrationSettings s = base;
    s.fit_cases.clear();
    s.holdout_cases.clear();
    s.field_metrics = false;
    s.progress = nullptr;
    // Dealt diagonally, (c + c / folds) mod folds: a suite lists a fixed number of load kinds
    // per side (x, y, twist in 2D), and plain round-robin with as many folds would hold out one
    // whole kind (every x traction) at once.
    for (int c = 0; c < static_cast<int>(training.size()); ++c)
      ((c + c / folds) % folds == f ? s.holdout_cases : s.fit_cases)
          .push_back(training[static_cast<size_t>(c)]);
    return s;
  }

  // Every fold's held-out error of the candidate (`configure` sets its fit on a fold's
  // settings); the first failing fold puts it out.
  template <class Configure>
  void score(const CalibrationSettings& base, CandidateScore& candidate,
             Configure&& configure) const {
    candidate.percent_e_rms.assign(training.size(), NAN);
    for (int f = 0; f < folds && candidate.failure.empty(); ++f) {
      CalibrationSettings s = fold_settings(base, f);
      configure(s, f);
      try {
        const CalibrationResult r = calibrate(problem, s);
        candidate.parameters = r.parameters;
        for (const auto& h : r.holdout) {
          const size_t c = static_cast<size_t>(std::find(training.begin(), training.end(), h.id) -
                                               training.begin());
          candidate.percent_e_rms[c] = h.control.percent_e_rms;
        }
      } catch (const std::runtime_error& e) {
        candidate.failure = e.what();
      }
    }
    candidate.worst = candidate.failure.empty() ? *std::max_element(candidate.percent_e_rms.begin(),
                                                                    candidate.percent_e_rms.end())
                                                : INFINITY;
    report(candidate);
  }

  void report(const CandidateScore& candidate) const {
    if (!settings.progress) return;
    settings.progress(
        "cross-validation: reach " + std::to_string(candidate.reach) +
        (candidate.volume_terms ? " with volume terms" : "") +
        (candidate.shear_terms ? " with shear terms" : "") +
        (candidate.strain_points > 0
             ? " with strain points (" + std::to_string(candidate.strain_points) + "/direction)"
             : "") +
        format(", gamma %g, prior weight %g", candidate.gamma, candidate.prior_weight) +
        (candidate.failure.empty() ? format(": worst held-out %%e_rms %.3g over %g cases",
                                            candidate.worst, static_cast<double>(training.size()))
                                   : ": failed"));
  }
};

// A candidate of the model kind of `mesh` with rest-length window `gamma`.
CandidateScore candidate_of(const SpringMeshOptions& mesh, double gamma) {
  CandidateScore candidate;
  candidate.reach = mesh.reach;
  candidate.volume_terms = mesh.volume_terms;
  candidate.shear_terms = mesh.shear_terms;
  candidate.strain_points = mesh.strain_points;
  candidate.gamma = gamma;
  return candidate;
}

// Stage, per model kind (base.mesh): the grouped candidates, one per gamma, then the per-spring
// ones, one per prior weight, each fold starting from the best grouping's optimum of that fold.
void score_model_kind(const CrossValidation& cv, const CalibrationSettings& base,
                      const GeneralisationOptions& options,
                      std::vector<CandidateScore>& candidates) {
  // A kind over the step budget is recorded, not fitted (its terms fix its cost).
  const double step_us = estimated_step_us(build_spring_mesh(cv.problem, base.mesh).network);
  std::string over_budget;
  if (base.max_step_us > 0.0 && step_us > base.max_step_us)
    over_budget = format("estimated engine step %.4g us over the budget max_step_us = %.4g",
                         step_us, base.max_step_us);
  int best_grouped = -1;
  for (double gamma : options.gammas) {
    CandidateScore candidate = candidate_of(base.mesh, gamma);
    candidate.estimated_step_us = step_us;
    candidate.failure = over_budget;
    cv.score(base, candidate, [gamma](CalibrationSettings& s, int) { s.gamma = gamma; });
    candidates.push_back(candidate);
    if (candidate.failure.empty() &&
        (best_grouped < 0 || candidate.worst < candidates[best_grouped].worst))
      best_grouped = static_cast<int>(candidates.size()) - 1;
  }
  if (best_grouped < 0 || options.prior_weights.empty()) return;
  const double gamma = candidates[static_cast<size_t>(best_grouped)].gamma;
  std::vector<std::vector<double>> prior(static_cast<size_t>(cv.folds));
  std::string failure;
  for (int f = 0; f < cv.folds && failure.empty(); ++f) {
    CalibrationSettings s = cv.fold_settings(base, f);
    s.gamma = gamma;
    try {
      prior[static_cast<size_t>(f)] = per_element_values(calibrate(cv.problem, s).fit_result);
    } catch (const std::runtime_error& e) {
      failure = e.what();
    }
  }
  for (double w : options.prior_weights) {
    CandidateScore candidate = candidate_of(base.mesh, gamma);
    candidate.prior_weight = w;
    candidate.estimated_step_us = step_us;
    candidate.failure = failure;
    cv.score(base, candidate, [&](CalibrationSettings& s, int f) {
      s.gamma = gamma;
      s.per_spring = true;
      s.prior_weight = w;
      s.per_spring_start = prior[static_cast<size_t>(f)];
    });
    candidates.push_back(candidate);
  }
}

// Stage: the best candidate refitted on every training case and measured on the validation
// cases; should its refit fail (a singular network), the next best.
void refit_best(const analysis::Problem& problem, const CalibrationSettings& base,
                const std::vector<std::string>& training, GeneralisationResult& result) {
  std::vector<int> order(result.candidates.size());
  for (size_t c = 0; c < order.size(); ++c) order[c] = static_cast<int>(c);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return result.candidates[static_cast<size_t>(a)].worst <
           result.candidates[static_cast<size_t>(b)].worst;
  });
  std::string failure;
  for (int c : order) {
    const CandidateScore& chosen = result.candidates[static_cast<size_t>(c)];
    if (!chosen.failure.empty()) continue;
    CalibrationSettings final_settings = base;
    final_settings.mesh.reach = chosen.reach;
    final_settings.mesh.volume_terms = chosen.volume_terms;
    final_settings.mesh.shear_terms = chosen.shear_terms;
    final_settings.mesh.strain_points = chosen.strain_points;
    final_settings.fit_cases = training;
    final_settings.gamma = chosen.gamma;
    try {
      if (chosen.prior_weight > 0.0) {
        CalibrationSettings grouped = final_settings;
        grouped.fit_cases = training;
        grouped.gamma = chosen.gamma;
        grouped.field_metrics = false;
        grouped.progress = nullptr;
        final_settings.per_spring = true;
        final_settings.prior_weight = chosen.prior_weight;
        final_settings.per_spring_start =
            per_element_values(calibrate(problem, grouped).fit_result);
      }
      result.calibration = calibrate(problem, final_settings);
      result.chosen = c;
      return;
    } catch (const std::runtime_error& e) {
      failure = e.what();
      result.warnings.push_back(format("the refit of candidate gamma %g, prior weight %g failed",
                                       chosen.gamma, chosen.prior_weight) +
                                " (" + failure + "); the next best candidate is used");
    }
  }
  // No refit was tried when every candidate failed its scoring (e.g. all over the step budget).
  if (failure.empty() && !result.candidates.empty()) failure = result.candidates[0].failure;
  throw std::runtime_error("generalisation: no candidate could be refitted (" + failure + ")");
}

// Stage: the chosen model's worst errors, a warning when they miss the target, and the warnings
// copied into the calibration's.
void summarise(const GeneralisationOptions& options, GeneralisationResult& result) {
  result.worst_fitted = worst_of(result.calibration.fit);
  result.worst_validation = worst_of(result.calibration.holdout);
  result.worst = std::max(result.worst_fitted, result.worst_validation);
  if (options.target_percent_e_rms > 0.0 && result.worst > options.target_percent_e_rms)
    result.warnings.push_back(
        format("the worst %%e_rms over fitted and validation load cases (%.3g) exceeds the "
               "target %.3g: the spring model does not reach the reference on every load",
               result.worst, options.target_percent_e_rms));
  for (const auto& w : result.warnings) result.calibration.warnings.push_back(w);
}

}  // namespace

GeneralisationResult calibrate_for_generalisation(const analysis::Problem& problem,
                                                  const CalibrationSettings& settings,
                                                  const GeneralisationOptions& options) {
  const std::vector<std::string> training = training_cases(problem, settings, options);
  CalibrationSettings base = shared_settings(problem, settings);
  check_model_kinds(options);

  const CrossValidation cv{problem, settings, training, options.folds};
  GeneralisationResult result;
  for (int reach : options.reaches)
    for (bool volume_terms : options.volume_terms)
      for (bool shear_terms : options.shear_terms)
        for (int strain_points : options.strain_points) {
          base.mesh.reach = reach;
          base.mesh.volume_terms = volume_terms;
          base.mesh.shear_terms = shear_terms;
          base.mesh.strain_points = strain_points;
          score_model_kind(cv, base, options, result.candidates);
        }

  refit_best(problem, base, training, result);
  summarise(options, result);
  return result;
}

}  // namespace isospring::fitting
