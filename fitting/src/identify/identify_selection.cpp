// The selection stages of the measured-data loop (loop_state.hpp): forward selection with a
// backward step after each addition, then the swap stage.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

#include "identify/loop_state.hpp"

namespace isospring::fitting::identify_loop {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

bool contains(const std::vector<const Effect*>& effects, const Effect* effect) {
  return std::find(effects.begin(), effects.end(), effect) != effects.end();
}

// The fit of the model with `effects` from `start`: the one made before, else a new one (kept
// when the model is linear); nullopt for a large-deformation model when `newton` is false.
std::optional<Fit> fit_of(const SelectionInputs& s, Selection& selection,
                          const std::vector<const Effect*>& effects, const Eigen::VectorXd& start,
                          FitStart how, bool newton) {
  if (const auto known = selection.linear_fits.find(effects); known != selection.linear_fits.end())
    return known->second;
  const Model model = build_model(s.setup, effects, start);
  if (model.forward->nonlinear() && !newton) return std::nullopt;
  const Fit fit = run_fit(s.setup, model, s.nominal.weights, nullptr, how);
  if (fit.ok && !model.forward->nonlinear()) selection.linear_fits[effects] = fit;
  return fit;
}

// The best candidate of a round so far.
struct RoundBest {
  double p = 2.0, bic = 0.0;
  const Effect* effect = nullptr;
  Fit fit;
};

// A round before its candidates: the current fit's RSS and residual, the unavailable effects.
SelectionRound start_round(const SelectionInputs& s, const Selection& selection) {
  SelectionRound round;
  round.rss = selection.current_fit.rss;
  round.residual = describe(
      s.setup, s.nominal,
      marker_misfit(s.setup, selection.current, selection.current_fit.theta, s.in.markers));
  for (const std::string& note : s.candidates.unavailable) {
    CandidateTest test;
    test.effect = note.substr(0, note.find(':'));
    test.note = note.substr(note.find(':') + 2);
    round.candidates.push_back(test);
  }
  return round;
}

// The expensive candidates last, so that the linear ones' best improvement is known when their
// score test is read.
std::vector<const Effect*> trial_order(const Candidates& candidates) {
  std::vector<const Effect*> order;
  for (const auto& effect : candidates.library)
    if (!effect->expensive()) order.push_back(effect.get());
  for (const auto& effect : candidates.library)
    if (effect->expensive()) order.push_back(effect.get());
  return order;
}

// Every candidate is fitted only when a score test at the current fit does not rule it out: far
// below the threshold it cannot become significant. The test costs one evaluation of the
// candidate's model, a fit many: a Newton solve each for the large-deformation candidate, a
// factorisation each once a stiffness gradient or a compliant support is in the model
// (measured on the suite's tube_graded: round 2's refits took 63 of 164 s). True when the test
// settles the candidate without a fit (screened out, contradicting its expected values or
// deferred); its outcome is then in `test`.
bool settled_by_score_test(const SelectionInputs& s, const Selection& selection,
                           const Effect& effect, const Model& model, const RoundBest& best,
                           CandidateTest& test) {
  const Eigen::VectorXd screening = effect.screening_values();
  if (screening.size() != effect.num_parameters()) return false;
  const Fit& current_fit = selection.current_fit;
  const double threshold =
      s.in.options.significance / static_cast<double>(s.candidates.library.size());
  auto settle = [&](const ScoreTest& score, std::string note) {
    test.score_f = score.f_statistic;
    test.f_statistic = score.f_statistic;
    test.p_value = score.p_value;
    test.rss = current_fit.rss - score.reduction;
    test.note = std::move(note);
    return true;
  };
  const ScoreTest score =
      score_test(s.setup, model, current_fit, screening, s.nominal.weights, s.candidates.allowance);
  if (!score.done) return false;
  test.score_f = score.f_statistic;
  if (score.p_value > 10.0 * threshold)
    return settle(score, "screened out by a score test at the current fit (F = " +
                             std::to_string(score.f_statistic) +
                             ", p = " + std::to_string(score.p_value) +
                             "; fitted only when p < 10 x the threshold)");
  // An effect whose physics fixes a parameter must find it near that value: its one-step
  // estimate from the score test is exact for a parameter the prediction is linear in (the
  // nonlinear blend weight), to first order in the others.
  const std::string contradiction = contradicted_expectation(
      effect, score.estimate, score.estimate_error, "the score test's one-step estimate", test);
  if (!contradiction.empty()) return settle(score, contradiction);
  // Significant, but explaining far less than a candidate already fitted this round: it cannot
  // be this round's choice (the score test's reduction is the first-order estimate of its
  // fit's, 10x below the best); the next round screens it again.
  const double best_reduction = best.effect ? current_fit.rss - best.fit.rss : 0.0;
  if (best.effect && best.p < threshold && score.reduction < 0.1 * best_reduction)
    return settle(
        score, "deferred: a score test at the current fit estimates an RSS reduction of " +
                   std::to_string(score.reduction) + ", below a tenth of " + best.effect->name() +
                   "'s " + std::to_string(best_reduction) + "; screened again next round");
  return false;
}

// The F-test and BIC of the candidate's fit against the current fit, widened by what the
// model's own error could contribute; whether the candidate may be this round's choice.
bool judge_fit(const SelectionInputs& s, Selection& selection, const Effect* effect,
               const Model& model, const Fit& fit, const Eigen::MatrixXd& covariance,
               CandidateTest& test) {
  const Fit& current_fit = selection.current_fit;
  std::string contradiction;
  if (!effect->expected_values().empty() && covariance.rows() == fit.theta.size()) {
    const Eigen::Index k = effect->num_parameters();
    const Eigen::VectorXd errors =
        covariance.diagonal().tail(k).cwiseMax(0.0).cwiseSqrt() *
        std::sqrt(fit.rss / std::max(1.0, static_cast<double>(fit.rows - fit.theta.size())));
    contradiction =
        contradicted_expectation(*effect, fit.theta.tail(k), errors, "the fitted", test);
  }
  // The part of the model's own discretisation error this candidate could absorb, |P e|^2, to
  // first order at its fit, plus two standard deviations of its cross term with the noise,
  // 2 x 2|P e|: the candidate must explain more than that to count (measured on the suite's
  // cantilever_frame: the Newton candidate gained 12 weighted RSS units, p = 5e-4, where the
  // estimated discretisation error at the markers was 25).
  double candidate_allowance = s.candidates.allowance;
  if (!s.candidates.model_error.empty()) {
    const double absorbed =
        project_on_new_columns(s.setup, model, fit.theta, current_fit.theta.size(),
                               s.nominal.weights, &s.candidates.model_error)
            .model_error;
    candidate_allowance = std::max(s.candidates.allowance, absorbed + 4.0 * std::sqrt(absorbed));
  }
  test.model_error_allowance = candidate_allowance;
  selection.allowance_of[effect] = candidate_allowance;
  test.rss = fit.rss;
  const int d1 = test.parameters;
  const int d2 = fit.rows - static_cast<int>(fit.theta.size());
  test.f_statistic =
      d2 > 0
          ? std::max(0.0, (current_fit.rss - fit.rss - candidate_allowance) / d1) / (fit.rss / d2)
          : 0.0;
  test.p_value = f_test_p_value(test.f_statistic, d1, d2);
  const double n = static_cast<double>(fit.rows);
  test.delta_bic = n * std::log(std::max(fit.rss + candidate_allowance, 1e-300) / current_fit.rss) +
                   d1 * std::log(n);
  // Both criteria must favour an effect: the F-test at a fixed significance lets ever smaller
  // systematic misfits through as the number of markers grows, BIC's penalty (ln n per
  // parameter) does not (measured on the suite's tube with undeclared self-weight: a clamp
  // compliance passed the F-test, p = 8e-4, with delta BIC +0.6).
  const bool bic_favours = !(test.delta_bic >= 0.0);
  if (!bic_favours && test.p_value < s.in.options.significance)
    test.note = "significant by the F-test, but BIC does not favour it (delta BIC " +
                std::to_string(test.delta_bic) + " >= 0): not added";
  if (!contradiction.empty()) test.note = contradiction;
  return bic_favours && contradiction.empty();
}

// One candidate of a round: screened, else fitted and tested; the round's best updated.
void try_candidate(const SelectionInputs& s, Selection& selection, const Effect* effect,
                   RoundBest& best, SelectionRound& round) {
  std::vector<const Effect*> trial = selection.chosen;
  trial.push_back(effect);
  const Model model = build_model(s.setup, trial, selection.current_fit.theta);
  s.in.say("trying " + effect->name());
  const auto fit_start = Clock::now();
  // What the candidate cost in factorisations of K (the linear models'; Newton's tangents are
  // counted by their own solvers), for the progress lines that profiles read.
  const FactorizationStats stats_before = factorization_stats(*s.setup.factorizations);
  auto report_cost = [&](const char* how) {
    const FactorizationStats now = factorization_stats(*s.setup.factorizations);
    s.in.say(effect->name() + " " + how + ": " +
             std::to_string(now.factorizations - stats_before.factorizations) +
             " factorisations, " +
             std::to_string(now.low_rank_updates - stats_before.low_rank_updates) +
             " low-rank updates, " + std::to_string(now.reuses - stats_before.reuses) + " reuses");
  };
  CandidateTest test;
  test.effect = effect->name();
  test.parameters = effect->num_parameters();
  if (settled_by_score_test(s, selection, *effect, model, best, test)) {
    test.seconds = seconds_since(fit_start);
    report_cost("settled by its score test");
    round.candidates.push_back(test);
    return;
  }
  const bool check_expectations = !effect->expected_values().empty();
  Eigen::MatrixXd covariance;
  const Fit fit = run_fit(s.setup, model, s.nominal.weights,
                          check_expectations ? &covariance : nullptr, FitStart::kNewParameters);
  if (fit.ok && !model.forward->nonlinear()) selection.linear_fits[trial] = fit;
  test.seconds = seconds_since(fit_start);
  report_cost("fitted");
  if (!fit.ok) {
    test.note = "fit failed: " + fit.message;
    round.candidates.push_back(test);
    return;
  }
  const bool eligible = judge_fit(s, selection, effect, model, fit, covariance, test);
  round.candidates.push_back(test);
  // Strong effects have p-values that underflow to 0 in double; among equal p-values the
  // candidate with the lower BIC wins (the most explained per parameter), not the first one
  // tried and not simply the largest.
  if (eligible && (test.p_value < best.p ||
                   (test.p_value == best.p && best.effect && test.delta_bic < best.bic))) {
    best.p = test.p_value;
    best.bic = test.delta_bic;
    best.effect = effect;
    best.fit = fit;
  }
}

// The change of the backward step that the tests favour most so far (p < 0: none yet).
struct BackwardChange {
  double p = -1.0;
  bool favoured_by_bic = false;
  std::vector<const Effect*> effects;
  Fit fit;
  std::string change;   // for the progress line
  std::string removed;  // for round.removed: the effect's name, or the replacement
};

// The F-test and BIC of going from the current effects to `reduced` (d1 parameters fewer); the
// change replaces `worst` when either criterion favours it and it is less significant.
void consider_change(const SelectionInputs& s, Selection& selection,
                     const std::vector<const Effect*>& reduced, const Eigen::VectorXd& start,
                     int d1, const std::string& change, const std::string& removed,
                     double effect_allowance, BackwardChange& worst) {
  if (d1 <= 0) return;
  const Fit fit = *fit_of(s, selection, reduced, start, FitStart::kNearOptimum, true);
  if (!fit.ok) return;
  const Fit& current_fit = selection.current_fit;
  const int d2 = current_fit.rows - static_cast<int>(current_fit.theta.size());
  const double f =
      std::max(0.0, (fit.rss - current_fit.rss - effect_allowance) / d1) / (current_fit.rss / d2);
  const double p = f_test_p_value(f, d1, d2);
  const double n = static_cast<double>(current_fit.rows);
  const double delta_bic =
      n * std::log(fit.rss / std::max(current_fit.rss + effect_allowance, 1e-300)) -
      d1 * std::log(n);
  const bool droppable = p > s.in.options.significance || delta_bic < 0.0;
  if (droppable && p > worst.p) {
    worst.p = p;
    worst.favoured_by_bic = delta_bic < 0.0;
    worst.effects = reduced;
    worst.fit = fit;
    worst.change = change;
    worst.removed = removed;
  }
}

// The swap that BIC favours most among every selected effect replaced by every other linear
// candidate; `seen` collects every alternative fitted.
struct SwapSearch {
  std::vector<Alternative> seen;
  double best_delta = -2.0;
  std::vector<const Effect*> best_effects;  // empty: no swap with delta BIC < -2
  Fit best_fit;
  Alternative best_swap;
};

SwapSearch search_swaps(const SelectionInputs& s, Selection& selection, double n) {
  auto bic = [&](const Fit& f) {
    return n * std::log(std::max(f.rss, 1e-300)) +
           static_cast<double>(f.theta.size()) * std::log(n);
  };
  const std::vector<const Effect*>& chosen = selection.chosen;
  SwapSearch search;
  for (size_t e = 0; e < chosen.size(); ++e)
    for (const auto& candidate : s.candidates.library) {
      if (contains(chosen, candidate.get())) continue;
      std::vector<const Effect*> swapped = chosen;
      swapped[e] = candidate.get();
      // A new fit is announced: the stage's fits are its time (a factorisation per evaluation
      // once the stiffness has parameters beyond E).
      if (!candidate->expensive() && !selection.linear_fits.count(swapped))
        s.in.say("swap stage: fitting " + candidate->name() + " in place of " + chosen[e]->name());
      // Not large-deformation models (Newton fits): the score test handled them.
      const std::optional<Fit> swap_fit =
          fit_of(s, selection, swapped,
                 start_replacing(s.setup, selection.current, selection.current_fit.theta, e,
                                 candidate.get()),
                 FitStart::kNewParameters, false);
      if (!swap_fit || !swap_fit->ok) continue;
      const Fit& fit = *swap_fit;
      const Alternative alternative{chosen[e]->name(), candidate->name(),
                                    bic(fit) - bic(selection.current_fit), false};
      search.seen.push_back(alternative);
      if (alternative.delta_bic < search.best_delta) {
        search.best_delta = alternative.delta_bic;
        search.best_effects = swapped;
        search.best_fit = fit;
        search.best_swap = alternative;
      }
    }
  return search;
}

}  // namespace

// Stage 5: forward selection. Each round tries every candidate not chosen yet and adds the most
// significant one when it passes the Bonferroni-corrected F-test and BIC favours it; the
// backward step follows every addition.
void select_forward(const SelectionInputs& s, IdentifyResult& result, Selection& selection) {
  selection.current = build_model(s.setup, selection.chosen, s.nominal.fit.theta);
  selection.current_fit = run_fit(s.setup, selection.current, s.nominal.weights);
  selection.p_before = static_cast<int>(selection.current_fit.theta.size());
  // Each effect can be added at most twice (once more after a backward step dropped it).
  const size_t max_rounds = 2 * s.candidates.library.size() + 1;
  while (static_cast<int>(selection.chosen.size()) < s.in.options.max_effects &&
         result.rounds.size() < max_rounds) {
    SelectionRound round = start_round(s, selection);
    int tried = 0;
    RoundBest best;
    for (const Effect* effect : trial_order(s.candidates)) {
      if (contains(selection.chosen, effect)) continue;
      ++tried;
      try_candidate(s, selection, effect, best, round);
    }
    const bool added = best.effect && best.p < s.in.options.significance / std::max(1, tried);
    if (added) {
      round.added = best.effect->name();
      selection.chosen.push_back(best.effect);
      s.in.say("added " + best.effect->name() + " (p = " + std::to_string(best.p) + ")");
      selection.current = build_model(s.setup, selection.chosen, best.fit.theta);
      selection.current_fit = best.fit;
      backward_step(s, round, selection);
    }
    result.rounds.push_back(round);
    if (!added) break;
  }
}

// The backward step (stepwise selection): an effect added earlier may only have stood in for
// the new one, and an effect may be more general than the data need now (a rigid motion per
// load case where one shared motion does). Drop an earlier effect, or replace an effect by its
// nested simpler version (Effect::simpler), while the F-test of the change fails or BIC favours
// the change; the least significant change first.
void backward_step(const SelectionInputs& s, SelectionRound& round, Selection& selection) {
  const auto& library = s.candidates.library;
  while (true) {
    const std::vector<const Effect*>& chosen = selection.chosen;
    const Eigen::VectorXd& theta = selection.current_fit.theta;
    BackwardChange worst;
    for (size_t e = 0; e < chosen.size(); ++e) {
      if (e + 1 < chosen.size() && chosen.size() > 1) {  // not the effect just added
        std::vector<const Effect*> reduced = chosen;
        reduced.erase(reduced.begin() + static_cast<std::ptrdiff_t>(e));
        consider_change(s, selection, reduced,
                        start_replacing(s.setup, selection.current, theta, e, nullptr),
                        chosen[e]->num_parameters(), "dropped " + chosen[e]->name(),
                        chosen[e]->name(), selection.allowance_of[chosen[e]], worst);
      }
      const std::string simpler = chosen[e]->simpler();
      const auto it = std::find_if(library.begin(), library.end(),
                                   [&](const auto& x) { return x->name() == simpler; });
      if (!simpler.empty() && it != library.end() && !contains(chosen, it->get())) {
        std::vector<const Effect*> replaced = chosen;
        replaced[e] = it->get();
        const std::string change = "replaced " + chosen[e]->name() + " by " + simpler;
        consider_change(s, selection, replaced,
                        start_replacing(s.setup, selection.current, theta, e, it->get()),
                        chosen[e]->num_parameters() - (*it)->num_parameters(), change, change,
                        selection.allowance_of[chosen[e]], worst);
      }
    }
    if (worst.p < 0.0) break;  // no change is favoured by either criterion
    s.in.say(worst.change + " (p = " + std::to_string(worst.p) +
             (worst.favoured_by_bic ? ", BIC favours the change)" : ")"));
    round.removed.push_back(worst.removed);
    selection.chosen = worst.effects;
    selection.current = build_model(s.setup, selection.chosen, worst.fit.theta);
    selection.current_fit = worst.fit;
  }
}

// Stage 6: the swap stage. Forward selection is path dependent: an effect that explains a bit of
// everything (a rigid motion per load case) can win the first round and leave nothing for the
// physical effect that explains the same data with fewer parameters (a stiff clamp, whose
// motion is fixed by its two spring stiffnesses). Each selected effect is replaced in turn by
// every other linear candidate and the models compared by BIC (not nested: no F-test). A swap
// with delta BIC < -2 (positive evidence) is taken, and the stage repeats; alternatives within
// 2 of the selection are reported as indistinguishable on these data.
void swap_effects(const SelectionInputs& s, IdentifyResult& result, Selection& selection) {
  const double n = static_cast<double>(selection.current_fit.rows);
  for (size_t pass = 0; pass < s.candidates.library.size() && !selection.chosen.empty(); ++pass) {
    SwapSearch search = search_swaps(s, selection, n);
    if (search.best_effects.empty()) {
      for (const Alternative& a : search.seen)
        if (std::abs(a.delta_bic) < 2.0) result.alternatives.push_back(a);
      break;
    }
    search.best_swap.swapped = true;
    result.alternatives.push_back(search.best_swap);
    s.in.say("swapped " + search.best_swap.replaced + " for " + search.best_swap.by +
             " (delta BIC = " + std::to_string(search.best_swap.delta_bic) + ")");
    selection.chosen = search.best_effects;
    selection.current = build_model(s.setup, selection.chosen, search.best_fit.theta);
    selection.current_fit = search.best_fit;
  }
}

}  // namespace isospring::fitting::identify_loop
