#pragma once
// The measured-data loop's state and its stages, private to the fitting module. identify()
// (identify.cpp) runs the stages in order:
//
//   1. fit_case_nominal       the nominal model (E, [nu]) on the case's discretisation
//   2. choose_discretisation  the discretisation check; a refined setup when it asks for one
//   3. fit_nominal            the nominal fit where the loop runs, its residual, the noise level
//                             and the selection's weights
//   4. collect_candidates     the effect library, the discretisation allowance and the model's
//                             own error at the observations                      (identify.cpp)
//   5. select_forward         forward selection; after each addition, backward_step
//   6. swap_effects           each selected effect replaced in turn by every other candidate
//                                                                      (identify_selection.cpp)
//   7. fit_final              the noise re-estimated from the final residual, the nominal and
//                             the final fit under its weights, with covariances
//   8. report_final           parameters, carried-over notes, residual summaries
//                                                                          (identify_final.cpp)
//   9. run_holdout            the hold-out refits                        (identify_holdout.cpp)
//
// Each stage's output is a struct of its own (CaseNominal, Discretisation, Nominal, Candidates,
// FinalFit) that later stages only read. The exception is Selection: stages 5 and 6 update it
// together, and stage 7 replaces its fit by the one under the final weights. Every stage writes
// its part of the IdentifyResult. The model and fit helpers are in identify_fit.cpp, a
// candidate's statistics in candidate_statistics.cpp.
#include <Eigen/Core>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "factorization_cache.hpp"
#include "fit_stopping.hpp"
#include "isospring/analysis/constraints.hpp"
#include "isospring/analysis/dof_map.hpp"
#include "isospring/fitting/effect.hpp"
#include "isospring/fitting/identify.hpp"
#include "isospring/fitting/identify_assembly.hpp"
#include "isospring/fitting/identify_model.hpp"

namespace isospring::fitting::identify_loop {

// ---------------------------------------------------------------------------------------------
// The model, its fits and the helpers every stage uses (identify_fit.cpp).

// Everything that stays fixed while effects come and go. Not copied or moved once made: the
// effect context points into it (dofs, constraints, stiffness).
struct Setup {
  const analysis::Problem* problem = nullptr;
  analysis::DofMap dofs;
  analysis::Constraints constraints;
  LameMatrices lame;
  int num_dofs = 0;  // dofs.num_dofs(), or the DOFs of a model without a problem
  // The stiffness of a model not split into Lame parts, at the prior modulus: K(theta) =
  // theta[0] K (an immersed model, whose Nitsche penalty scales with E but is not linear in
  // lambda and mu apart). Empty for body-fitted models.
  Eigen::SparseMatrix<double> scaled_stiffness;
  ModelLoads loads;  // the context's loads of a model without a problem
  EffectContext context;
  int dim = 3;
  int material_parameters = 1;
  std::vector<Eigen::VectorXd> nominal_loads;  // per load case
  std::vector<Observation> observations;       // per load case
  std::vector<Eigen::VectorXd> measured;       // per load case, observation space
  std::vector<Eigen::VectorXd> sigma;          // per load case, per row (0: use the global one)
  Eigen::Vector3d component_weight = Eigen::Vector3d::Ones();  // IdentifyOptions::component_weights
  std::vector<std::vector<int>> markers;  // per load case: marker indices, in row order
  std::map<std::string, int> case_index;  // load case id -> index
  // The last K_ff factorisation, shared by every model of the loop (identify_model.hpp).
  std::shared_ptr<FactorizationCache> factorizations = make_factorization_cache();
  // What the setup had to adapt, for the report (an immersed stiffness stabilised further).
  std::vector<std::string> warnings;
  // A fit ends once a step and its Gauss-Newton prediction gain less RSS than this, in units of
  // the residual variance (fit_stopping.hpp); 0: only Ceres' relative tolerances end fits.
  double negligible_rss = kNegligibleRss;
};

struct Fit {
  bool ok = false;
  Eigen::VectorXd theta;
  double rss = 0.0;
  int rows = 0;  // observations with weight
  std::string message;
  int iterations = 0;               // of the last Ceres solve
  bool stopped_negligible = false;  // ended by the negligible-decrease rule (fit_stopping.hpp)
};

struct Model {
  std::unique_ptr<ForwardModel> forward;
  Eigen::VectorXd initial;
  std::vector<std::pair<int, int>> blocks;  // per effect: first parameter, count
  Eigen::VectorXd lower, upper;             // the effects' parameter bounds (Effect::*_bounds)
};

// How a fit starts: near its optimum (a refit under other weights, a model fitted before less an
// effect) or with an effect's parameters at their initial values.
enum class FitStart { kNearOptimum, kNewParameters };

// The residual of the model at theta at every marker, and what the noise estimate groups it by.
struct MarkerResidual {
  std::vector<Eigen::Vector3d> predicted, residual, positions;
  std::vector<int> group;  // load case index
};

// Validates the inputs and builds everything that stays fixed while effects come and go.
void make_setup(Setup& setup, const analysis::Problem& problem, const std::vector<Marker>& markers,
                const std::vector<MarkerPlacement>& placements, bool fit_poisson,
                const std::function<void(const std::string&)>& say);
// `cache`: the factorisation cache the model solves with; null: the loop's (setup.factorizations).
Model build_model(const Setup& setup, const std::vector<const Effect*>& effects,
                  const Eigen::VectorXd& warm_start,
                  std::shared_ptr<FactorizationCache> cache = nullptr);
// Starting values for a refit of `current`'s effects with effect e replaced by `replacement`
// (dropped when null): the material's and the kept effects' fitted values from theta, the
// replacement's own initial values.
Eigen::VectorXd start_replacing(const Setup& setup, const Model& current,
                                const Eigen::VectorXd& theta, size_t e, const Effect* replacement);
std::vector<Eigen::VectorXd> make_weights(const Setup& setup, double sigma,
                                          const std::vector<bool>& use_marker);
// IdentifyOptions::component_weights (or the mean-|u| normalisation) for a model of dimension
// `dim`, normalised to rms 1.
Eigen::Vector3d component_weights(const IdentifyOptions& options,
                                  const std::vector<Marker>& markers, int dim);
// The noise estimate of residuals weighted per component (sigma_c = sigma / w_c).
double weighted_noise(const Setup& setup, const std::vector<Eigen::Vector3d>& positions,
                      std::vector<Eigen::Vector3d> residuals, const std::vector<int>& group);
// The Gauss-Newton covariance of the parameters at theta (weights 1 / sigma: unit noise).
Eigen::MatrixXd fit_covariance(const Model& model, const Eigen::VectorXd& theta,
                               const std::vector<Eigen::VectorXd>& weights);
Fit run_fit(const Setup& setup, const Model& model, const std::vector<Eigen::VectorXd>& weights,
            Eigen::MatrixXd* covariance = nullptr, FitStart start = FitStart::kNearOptimum);
// `fit` (made with weights `from`) under weights `to` without a refit when `to` is a uniform
// multiple of `from`; nullopt otherwise.
std::optional<Fit> reweighted(const Fit& fit, const std::vector<Eigen::VectorXd>& from,
                              const std::vector<Eigen::VectorXd>& to);
ErrorSummary summarize(const std::vector<Eigen::Vector3d>& residuals, const std::vector<int>& rows,
                       int dim);
// Model displacement at every marker for theta.
std::vector<Eigen::Vector3d> marker_predictions(const Setup& setup, const Model& model,
                                                const Eigen::VectorXd& theta, size_t markers);
// Model displacement at every marker with the named effects at the given parameter values
// (the material's E relative to the prior is 1); `caller` names the public function in errors.
std::vector<Eigen::Vector3d> simulate_with_effects(
    Setup& setup, size_t markers,
    const std::vector<std::pair<std::string, Eigen::VectorXd>>& effects, const std::string& caller);
// Measured minus predicted at every marker for theta.
std::vector<Eigen::Vector3d> marker_misfit(const Setup& setup, const Model& model,
                                           const Eigen::VectorXd& theta,
                                           const std::vector<Marker>& markers);
MarkerResidual marker_residual(const Setup& setup, const Model& model, const Eigen::VectorXd& theta,
                               const std::vector<Marker>& markers);

// ---------------------------------------------------------------------------------------------
// The statistics of a candidate (candidate_statistics.cpp).

// The part of the weighted residual r, and of the weighted model error e, along the Jacobian
// columns D of parameters first_new.. that the earlier parameters' columns J cannot already
// explain: |P r|^2 and |P e|^2 with P the projection on (I - J J^+) D, at parameters theta.
struct NewColumnProjection {
  bool done = false;
  int rank = 0;
  double residual = 0.0, model_error = 0.0, rss = 0.0;
  /// One Gauss-Newton step of the new parameters from theta (the earlier ones refitted with them
  /// to first order) and its standard errors, with the noise variance estimated from what is
  /// left, (rss - residual) / (rows - total); empty when the new columns are rank deficient.
  Eigen::VectorXd step, step_error;
};

NewColumnProjection project_on_new_columns(const Setup& setup, const Model& model,
                                           const Eigen::VectorXd& theta, Eigen::Index first_new,
                                           const std::vector<Eigen::VectorXd>& weights,
                                           const std::vector<Eigen::VectorXd>* model_error);

// The score (Lagrange-multiplier) test of adding a candidate to the current fit: with the
// candidate at its neutral values the model equals the current one, so the residual r is the
// current residual, and to first order the best the candidate can do is to remove |P r|^2
// (project_on_new_columns). F and p as in the F-test.
struct ScoreTest {
  bool done = false;
  double reduction = 0.0, f_statistic = 0.0, p_value = 1.0;
  int q = 0, d2 = 0;  // the F-test's degrees of freedom
  double rss = 0.0;   // at the current fit
  /// The candidate's parameters after one Gauss-Newton step from its neutral values, and their
  /// standard errors (empty when not estimable).
  Eigen::VectorXd estimate, estimate_error;

  /// F and p again with another allowance.
  void widen(double allowance);
};

ScoreTest score_test(const Setup& setup, const Model& candidate, const Fit& current,
                     const Eigen::VectorXd& neutral, const std::vector<Eigen::VectorXd>& weights,
                     double allowance);

// The first expected value of `effect` (Effect::expected_values) that its estimated parameters
// contradict, as a note for the report; empty when every one is consistent or not estimable.
// Records the estimate in the candidate's test.
std::string contradicted_expectation(const Effect& effect, const Eigen::VectorXd& values,
                                     const Eigen::VectorXd& errors, const std::string& how,
                                     CandidateTest& test);

// ---------------------------------------------------------------------------------------------
// The stages' state, in the order the stages make it.

// The inputs of identify() and what every stage reads alongside them.
struct LoopInputs {
  const analysis::Problem& problem;
  const std::vector<Marker>& markers;
  const std::vector<MarkerPlacement>& placements;
  const IdentifyOptions& options;
  int element_threads = 1;        // the assembly's threads, and the hold-out folds'
  std::vector<bool> all_markers;  // every marker counts
  std::vector<int> all_rows;      // every marker index, in order
  // A model without a body-fitted problem (identify_immersed.cpp): builds the setup in place of
  // make_setup, and `problem` only names the material and the load cases. Empty: body-fitted.
  std::function<void(Setup&)> custom_setup;
  std::string no_discretisation_check;  // why the check does not run on such a model
  // The discretisation check of such a model, when it has one: fills `check` from the case's
  // setup, its nominal fit's parameters and the noise level, and returns the setup of the level
  // chosen (null: the case's own).
  std::function<std::unique_ptr<Setup>(const Setup& case_setup, const Eigen::VectorXd& theta,
                                       double noise, DiscretizationCheck& check)>
      custom_check;

  void say(const std::string& message) const {
    if (options.progress) options.progress(message);
  }
  std::function<void(const std::string&)> progress() const {
    return [this](const std::string& message) { say(message); };
  }
};

// The whole loop, stages 1 to 9 (identify.cpp).
IdentifyResult run_loop(const LoopInputs& in);

// Stage 1: the case's own discretisation and its nominal fit, made with a provisional noise
// level (uniform weights: the estimate does not depend on it).
struct CaseNominal {
  Setup setup;
  double provisional = 0.0;  // the provisional noise level, also the fallback of every estimate
  Model baseline;            // no effects
  Fit fit;
};

// Stage 2: where the loop runs. Invariant: `refined_setup` is set exactly when the
// discretisation check chose a finer level, and then points into `refined_problem` (a body-
// fitted model; an immersed level's setup holds all it needs).
struct Discretisation {
  std::optional<analysis::Problem> refined_problem;
  std::unique_ptr<Setup> refined_setup;
};

// The setup the loop runs on: the refined one when there is one, else the case's.
inline const Setup& loop_setup(const CaseNominal& case_nominal, const Discretisation& chosen) {
  return chosen.refined_setup ? *chosen.refined_setup : case_nominal.setup;
}

// Stage 3: the nominal model on the loop's setup, and the selection's weights (1 / sigma at the
// first noise estimate, result.noise_estimate).
struct Nominal {
  std::optional<Model> refined_baseline;  // set with a refined setup
  const Model* baseline = nullptr;        // refined_baseline, else the case's baseline
  Fit fit;
  MarkerResidual residual;
  std::vector<std::string> case_ids;  // load case ids, in order
  std::vector<Eigen::VectorXd> weights;
};

// Stage 4: the effects to try, and what the F-tests are widened by.
struct Candidates {
  std::vector<std::unique_ptr<Effect>> library;  // the effects that apply to the model
  std::vector<std::string> unavailable;          // "name: why not", the others
  double allowance = 0.0;                        // result.discretization_allowance
  // The discretisation check's estimate of the model's own error at the observations (per load
  // case, rows as measured); empty without one.
  std::vector<Eigen::VectorXd> model_error;
};

// What the selection stages (5 and 6) read and do not change.
struct SelectionInputs {
  const LoopInputs& in;
  const Setup& setup;
  const Nominal& nominal;
  const Candidates& candidates;
};

// Stages 5 and 6: the selection so far. Invariants: `current` is the model of `chosen` (in
// order) and `current_fit` its fit under the selection's weights; every fit in `linear_fits` was
// made under those weights.
struct Selection {
  std::vector<const Effect*> chosen;
  Model current;
  Fit current_fit;
  int p_before = 0;  // the nominal model's parameter count
  // Allowance of each effect, from the round that added it (for the backward step).
  std::map<const Effect*, double> allowance_of;
  // The fits of the linear models tried so far, by their effects (in order). The backward step
  // and the swap stage try models fitted before (one effect replacing the first chosen is a
  // model of round 1): a refit would repeat the fit (measured on the suite's tube_graded: 6 s
  // for one support_compliance refit).
  std::map<std::vector<const Effect*>, Fit> linear_fits;
};

// Stage 7: the final fit under the weights of the final noise estimate.
struct FinalFit {
  std::vector<Eigen::VectorXd> weights;
  double rss_before = 0.0;  // the nominal model's weighted RSS under `weights`
  Eigen::MatrixXd covariance;
};

// ---------------------------------------------------------------------------------------------
// The stages.

void fit_case_nominal(const LoopInputs& in, CaseNominal& out);  // identify.cpp
void choose_discretisation(const LoopInputs& in, const CaseNominal& case_nominal,
                           IdentifyResult& result, Discretisation& out);
void fit_nominal(const LoopInputs& in, const CaseNominal& case_nominal,
                 const Discretisation& chosen, IdentifyResult& result, Nominal& out);
void collect_candidates(const LoopInputs& in, const Setup& setup, const Nominal& nominal,
                        IdentifyResult& result, Candidates& out);
// The residual's description for the report, grouped and scaled like the nominal one's.
ResidualDescription describe(const Setup& setup, const Nominal& nominal,
                             const std::vector<Eigen::Vector3d>& residual);

void select_forward(const SelectionInputs& s, IdentifyResult& result,
                    Selection& selection);  // identify_selection.cpp
void backward_step(const SelectionInputs& s, SelectionRound& round, Selection& selection);
void swap_effects(const SelectionInputs& s, IdentifyResult& result, Selection& selection);

void fit_final(const LoopInputs& in, const Setup& setup, const CaseNominal& case_nominal,
               const Nominal& nominal, IdentifyResult& result, Selection& selection,
               FinalFit& out);  // identify_final.cpp
void report_final(const LoopInputs& in, const CaseNominal& case_nominal,
                  const Discretisation& chosen, const Nominal& nominal, const Selection& selection,
                  const FinalFit& final_fit, IdentifyResult& result);

void run_holdout(const LoopInputs& in, const Setup& setup, const Nominal& nominal,
                 const Selection& selection, IdentifyResult& result);  // identify_holdout.cpp
// The cache of the final model (the loop's, setup.factorizations) holding the factor of its K at
// its fitted parameters, for the folds to copy (identify_holdout.cpp; run_holdout calls it).
void factor_final_model(const Selection& selection);
// A hold-out fold's cache: the loop's large-deformation starts and kept tangents, shared.
std::shared_ptr<FactorizationCache> fold_cache(FactorizationCache& loop);

}  // namespace isospring::fitting::identify_loop
