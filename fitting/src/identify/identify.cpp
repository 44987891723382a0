// The identification loop: baseline fit, F-test selection of effects, covariance, hold-out check.
#include "isospring/fitting/identify.hpp"

#include <ceres/ceres.h>
#include <omp.h>
#include <Eigen/QR>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <map>
#include <memory>
#include <optional>

#include "factorization_cache.hpp"
#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/constraints.hpp"
#include "isospring/analysis/dof_map.hpp"
#include "isospring/analysis/thread_scope.hpp"
#include "isospring/analysis/validation.hpp"
#include "isospring/fitting/effect.hpp"
#include "isospring/fitting/identify_assembly.hpp"
#include "isospring/fitting/identify_model.hpp"
#include "isospring/nurbs/error.hpp"
#include "quiet_solver_warnings.hpp"

namespace isospring::fitting {

namespace {

// Lame parameters of theta = (E / E_prior, [nu]) with exact gradients.
Coefficient lame_coefficient(bool lambda, analysis::Formulation formulation, double e_prior,
                             double nu_prior, int nu_index) {
  return [=](const Eigen::VectorXd& theta, Eigen::VectorXd* gradient) {
    const double e = e_prior * theta[0];
    const double nu = nu_index >= 0 ? theta[nu_index] : nu_prior;
    double g, dg;  // value per unit E and its derivative in nu
    if (!lambda) {
      g = 0.5 / (1.0 + nu);
      dg = -0.5 / ((1.0 + nu) * (1.0 + nu));
    } else if (formulation == analysis::Formulation::kPlaneStress) {
      const double den = 1.0 - nu * nu;
      g = nu / den;
      dg = (1.0 + nu * nu) / (den * den);
    } else {
      const double den = (1.0 + nu) * (1.0 - 2.0 * nu);
      g = nu / den;
      dg = (1.0 + 2.0 * nu * nu) / (den * den);
    }
    if (gradient) {
      gradient->setZero(theta.size());
      (*gradient)[0] = e_prior * g;
      if (nu_index >= 0) (*gradient)[nu_index] = e * dg;
    }
    return e * g;
  };
}

// Everything that stays fixed while effects come and go.
struct Setup {
  const analysis::Problem* problem = nullptr;
  analysis::DofMap dofs;
  analysis::Constraints constraints;
  LameMatrices lame;
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
};

struct Fit {
  bool ok = false;
  Eigen::VectorXd theta;
  double rss = 0.0;
  int rows = 0;  // observations with weight
  std::string message;
};

class DataCost : public ceres::CostFunction {
 public:
  DataCost(const ForwardModel& model, const std::vector<Eigen::VectorXd>& measured,
           const std::vector<Eigen::VectorXd>& weights)
      : model_(model), measured_(measured), weights_(weights) {
    int rows = 0;
    for (const auto& m : measured) rows += static_cast<int>(m.size());
    set_num_residuals(rows);
    mutable_parameter_block_sizes()->push_back(model.num_parameters());
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const int p = model_.num_parameters();
    const Eigen::VectorXd theta = Eigen::Map<const Eigen::VectorXd>(parameters[0], p);
    const bool with_jacobian = jacobians && jacobians[0];
    ModelEvaluation eval;
    try {
      eval = model_.evaluate(theta, with_jacobian);
    } catch (const std::runtime_error&) {
      return false;  // Ceres shortens the step
    }
    int row = 0;
    for (size_t l = 0; l < measured_.size(); ++l)
      for (Eigen::Index k = 0; k < measured_[l].size(); ++k, ++row) {
        const double w = weights_[l][k];
        residuals[row] = w * (measured_[l][k] - eval.predictions[l][k]);
        if (with_jacobian)
          for (int j = 0; j < p; ++j) jacobians[0][row * p + j] = -w * eval.jacobians[l](k, j);
      }
    return true;
  }

 private:
  const ForwardModel& model_;
  const std::vector<Eigen::VectorXd>& measured_;
  const std::vector<Eigen::VectorXd>& weights_;
};

struct Model {
  std::unique_ptr<ForwardModel> forward;
  Eigen::VectorXd initial;
  std::vector<std::pair<int, int>> blocks;  // per effect: first parameter, count
};

// `cache`: the factorisation cache the model solves with; null: the loop's (setup.factorizations).
Model build_model(const Setup& setup, const std::vector<const Effect*>& effects,
                  const Eigen::VectorXd& warm_start,
                  std::shared_ptr<FactorizationCache> cache = nullptr) {
  ModelTerms terms;
  terms.num_parameters = setup.material_parameters;
  for (const Effect* effect : effects) terms.num_parameters += effect->num_parameters();
  terms.stiffness.push_back({setup.lame.lambda_part, setup.context.lambda});
  terms.stiffness.push_back({setup.lame.mu_part, setup.context.mu});
  for (size_t l = 0; l < setup.nominal_loads.size(); ++l)
    terms.loads.push_back({static_cast<int>(l), setup.nominal_loads[l], constant_coefficient(1.0)});
  Model model;
  model.initial.resize(terms.num_parameters);
  model.initial[0] = 1.0;
  if (setup.material_parameters > 1) model.initial[1] = setup.problem->material.poisson_ratio;
  int first = setup.material_parameters;
  for (const Effect* effect : effects) {
    effect->add_terms(setup.context, first, terms);
    model.initial.segment(first, effect->num_parameters()) = effect->initial_values();
    model.blocks.emplace_back(first, effect->num_parameters());
    first += effect->num_parameters();
  }
  // Warm start: the parameters already fitted keep their values (effects are appended).
  const Eigen::Index keep = std::min(warm_start.size(), model.initial.size());
  model.initial.head(keep) = warm_start.head(keep);
  model.forward = std::make_unique<ForwardModel>(
      std::move(terms), setup.observations, setup.constraints.dofs, setup.constraints.values,
      setup.dofs.num_dofs(), static_cast<int>(setup.observations.size()),
      cache ? std::move(cache) : setup.factorizations);
  return model;
}

// Starting values for a refit of `current`'s effects with effect e replaced by `replacement`
// (dropped when null): the material's and the kept effects' fitted values from theta, the
// replacement's own initial values.
Eigen::VectorXd start_replacing(const Setup& setup, const Model& current,
                                const Eigen::VectorXd& theta, size_t e, const Effect* replacement) {
  Eigen::VectorXd start = theta.head(setup.material_parameters);
  for (size_t k = 0; k < current.blocks.size(); ++k) {
    const Eigen::VectorXd values =
        k != e ? Eigen::VectorXd(theta.segment(current.blocks[k].first, current.blocks[k].second))
        : replacement ? replacement->initial_values()
                      : Eigen::VectorXd();
    start.conservativeResize(start.size() + values.size());
    start.tail(values.size()) = values;
  }
  return start;
}

Eigen::Index setup_rows(const std::vector<Eigen::VectorXd>& weights) {
  Eigen::Index rows = 0;
  for (const auto& w : weights) rows += w.size();
  return rows;
}

std::vector<Eigen::VectorXd> make_weights(const Setup& setup, double sigma,
                                          const std::vector<bool>& use_marker) {
  std::vector<Eigen::VectorXd> weights;
  for (size_t l = 0; l < setup.measured.size(); ++l) {
    Eigen::VectorXd w(setup.measured[l].size());
    for (Eigen::Index k = 0; k < w.size(); ++k) {
      const int marker = setup.markers[l][static_cast<size_t>(k / setup.dim)];
      const double s = setup.sigma[l][k] > 0.0 ? setup.sigma[l][k] : sigma;
      w[k] =
          use_marker[static_cast<size_t>(marker)] ? setup.component_weight[k % setup.dim] / s : 0.0;
    }
    weights.push_back(w);
  }
  return weights;
}

// IdentifyOptions::component_weights (or the mean-|u| normalisation) for a model of dimension
// `dim`, normalised to rms 1.
Eigen::Vector3d component_weights(const IdentifyOptions& options,
                                  const std::vector<Marker>& markers, int dim) {
  Eigen::Vector3d w = Eigen::Vector3d::Ones();
  const char* axes = "xyz";
  if (options.component_weights_mean_abs) {
    if (!options.component_weights.empty())
      throw nurbs::InputError(
          "measurements.component_weights: give either weights or \"mean_abs\", not both");
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const Marker& m : markers) mean += m.displacement.cwiseAbs();
    mean /= static_cast<double>(markers.size());
    for (int c = 0; c < dim; ++c) {
      if (!(mean[c] > 0.0))
        throw nurbs::InputError(std::string("measurements.component_weights: \"mean_abs\" needs "
                                            "non-zero measured ") +
                                axes[c] + " displacements; give the weights as numbers instead");
      w[c] = 1.0 / mean[c];
    }
  } else if (!options.component_weights.empty()) {
    if (static_cast<int>(options.component_weights.size()) != dim)
      throw nurbs::InputError("measurements.component_weights: " + std::to_string(dim) +
                              " weights expected (one per displacement component of the model), "
                              "got " +
                              std::to_string(options.component_weights.size()));
    for (int c = 0; c < dim; ++c) {
      const double v = options.component_weights[static_cast<size_t>(c)];
      if (!(std::isfinite(v) && v > 0.0))
        throw nurbs::InputError(std::string("measurements.component_weights[") + std::to_string(c) +
                                "]: must be a positive number");
      w[c] = v;
    }
  }
  double sum = 0.0;
  for (int c = 0; c < dim; ++c) sum += w[c] * w[c];
  return w / std::sqrt(sum / dim);
}

// The noise estimate of residuals weighted per component: with component weights w_c the noise
// model is sigma_c = sigma / w_c, and sigma is estimated from the residual components times w_c
// (so that weights w_c / sigma make every row's noise 1 and the covariance is right).
double weighted_noise(const Setup& setup, const std::vector<Eigen::Vector3d>& positions,
                      std::vector<Eigen::Vector3d> residuals, const std::vector<int>& group) {
  for (auto& r : residuals) r = r.cwiseProduct(setup.component_weight);
  return estimate_noise(positions, residuals, group, setup.dim);
}

// The Gauss-Newton covariance of the parameters at theta (weights 1 / sigma: unit noise). The
// weighted Jacobian is scaled by columns (gauss_newton_covariance), not handed to
// ceres::Covariance, whose unscaled SVD declares the problem rank deficient when parameter
// scales differ by 1e6 (E ratio ~1, rotations ~1e-5).
Eigen::MatrixXd fit_covariance(const Model& model, const Eigen::VectorXd& theta,
                               const std::vector<Eigen::VectorXd>& weights) {
  const ModelEvaluation eval = model.forward->evaluate(theta, true);
  const int p = static_cast<int>(theta.size());
  Eigen::MatrixXd jacobian(setup_rows(weights), p);
  Eigen::Index row = 0;
  for (size_t l = 0; l < weights.size(); ++l)
    for (Eigen::Index k = 0; k < weights[l].size(); ++k, ++row)
      jacobian.row(row) = weights[l][k] * eval.jacobians[l].row(k);
  return gauss_newton_covariance(jacobian);
}

// How a fit starts: near its optimum (a refit under other weights, a model fitted before less an
// effect) or with an effect's parameters at their initial values.
enum class FitStart { kNearOptimum, kNewParameters };

Fit run_fit(const Setup& setup, const Model& model, const std::vector<Eigen::VectorXd>& weights,
            Eigen::MatrixXd* covariance = nullptr, FitStart start = FitStart::kNearOptimum) {
  const QuietSolverWarnings quiet;
  Fit fit;
  fit.theta = model.initial;
  ceres::Problem::Options problem_options;
  problem_options.cost_function_ownership = ceres::TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  problem.AddResidualBlock(new DataCost(*model.forward, setup.measured, weights), nullptr,
                           fit.theta.data());
  problem.SetParameterLowerBound(fit.theta.data(), 0, 1e-3);
  if (setup.material_parameters > 1) {
    problem.SetParameterLowerBound(fit.theta.data(), 1, -0.9);
    problem.SetParameterUpperBound(fit.theta.data(), 1, 0.49);
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = 100;
  // 1e-10: the parameters then stop within 2e-4 of their standard errors of where 1e-12 ends
  // (the suite's tube_graded), and the fits stop spending evaluations on steps that round-off
  // rejects at the optimum (one factorisation each once the stiffness has parameters beyond E:
  // 21 of tube_graded's 121 s).
  options.function_tolerance = 1e-10;
  options.gradient_tolerance = 1e-14;
  options.parameter_tolerance = 1e-10;
  options.logging_type = ceres::SILENT;
  // No line search along a step projected onto the bounds: it evaluates the Jacobian at every
  // trial point (a Newton tangent and its factorisation per load case for the large-deformation
  // candidate, then again at the accepted point), and the bounds here are only guards of the
  // physical range (E > 0, nu < 0.5) that a fit does not end on. Steps are still projected.
  options.max_num_line_search_step_size_iterations = 0;
  // New parameters start far from their optimum, where the predictions are nonlinear in some
  // (1 / (1 + a . x), 1 / k) and Ceres' default first radius (1e4: Gauss-Newton steps) overshoots,
  // each rejected step costing a factorisation once the stiffness has parameters; they are of
  // order one (relative E and gradients, log stiffnesses), so the first steps are damped with
  // radius 100. Near the optimum Gauss-Newton steps are right. Measured on the suite's
  // tube_graded: the gradient's round-1 fit 10 -> 7 iterations with radius 100, but a hold-out
  // fold's refit 3 -> 6.
  if (start == FitStart::kNewParameters) options.initial_trust_region_radius = 100.0;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  fit.ok = summary.IsSolutionUsable() && std::isfinite(summary.final_cost);
  fit.message = summary.message;
  fit.rss = 2.0 * summary.final_cost;
  for (const auto& w : weights) fit.rows += static_cast<int>((w.array() > 0.0).count());
  if (fit.ok && covariance) *covariance = fit_covariance(model, fit.theta, weights);
  return fit;
}

// `fit` (made with weights `from`) under weights `to`: when `to` is a uniform multiple a of
// `from`, the cost is a^2 times the old one everywhere, so the optimum is the same and only the
// RSS scales (no refit, which would spend its evaluations confirming the optimum: a
// factorisation each once the stiffness has more parameters than E). nullopt otherwise.
std::optional<Fit> reweighted(const Fit& fit, const std::vector<Eigen::VectorXd>& from,
                              const std::vector<Eigen::VectorXd>& to) {
  if (!fit.ok || from.size() != to.size()) return std::nullopt;
  double ratio = 0.0;
  for (size_t l = 0; l < from.size(); ++l) {
    if (from[l].size() != to[l].size()) return std::nullopt;
    for (Eigen::Index k = 0; k < from[l].size(); ++k) {
      if ((from[l][k] == 0.0) != (to[l][k] == 0.0)) return std::nullopt;
      if (from[l][k] == 0.0) continue;
      const double a = to[l][k] / from[l][k];
      if (ratio == 0.0) ratio = a;
      if (!(std::abs(a - ratio) <= 1e-14 * ratio)) return std::nullopt;
    }
  }
  if (!(ratio > 0.0)) return std::nullopt;
  Fit out = fit;
  out.rss *= ratio * ratio;
  return out;
}

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
                                           const std::vector<Eigen::VectorXd>* model_error) {
  NewColumnProjection out;
  const Eigen::Index total = theta.size();
  ModelEvaluation eval;
  try {
    eval = model.forward->evaluate(theta, true);
  } catch (const std::exception&) {
    return out;
  }
  const Eigen::Index rows = setup_rows(weights);
  Eigen::MatrixXd jacobian(rows, total);
  Eigen::VectorXd residual(rows);
  Eigen::VectorXd error = Eigen::VectorXd::Zero(rows);
  Eigen::Index row = 0;
  for (size_t l = 0; l < weights.size(); ++l)
    for (Eigen::Index k = 0; k < weights[l].size(); ++k, ++row) {
      jacobian.row(row) = weights[l][k] * eval.jacobians[l].row(k);
      residual[row] = weights[l][k] * (setup.measured[l][k] - eval.predictions[l][k]);
      if (model_error) error[row] = weights[l][k] * (*model_error)[l][k];
    }
  // Column scaling keeps the projection's conditioning independent of the parameters' units.
  Eigen::VectorXd scale = jacobian.colwise().norm().transpose();
  for (Eigen::Index c = 0; c < total; ++c)
    if (scale[c] > 0.0) jacobian.col(c) /= scale[c];
  const Eigen::MatrixXd earlier = jacobian.leftCols(first_new);
  Eigen::MatrixXd added = jacobian.rightCols(total - first_new);
  added -= earlier * earlier.colPivHouseholderQr().solve(added);
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(added);
  out.rank = static_cast<int>(qr.rank());
  if (out.rank == 0) return out;
  out.rss = residual.squaredNorm();
  const Eigen::VectorXd step = qr.solve(residual);
  out.residual = std::min((added * step).squaredNorm(), out.rss);
  if (model_error) out.model_error = (added * qr.solve(error)).squaredNorm();
  const Eigen::Index dof = rows - total;
  if (out.rank == added.cols() && dof > 0) {
    // The step and covariance of the new parameters are those of the regression on the
    // orthogonalised columns (Frisch-Waugh-Lovell), undone column scaling.
    const double variance = (out.rss - out.residual) / static_cast<double>(dof);
    const Eigen::MatrixXd inverse_normal =
        (added.transpose() * added)
            .ldlt()
            .solve(Eigen::MatrixXd::Identity(added.cols(), added.cols()));
    out.step.resize(added.cols());
    out.step_error.resize(added.cols());
    for (Eigen::Index c = 0; c < added.cols(); ++c) {
      const double s = scale[first_new + c] > 0.0 ? scale[first_new + c] : 1.0;
      out.step[c] = step[c] / s;
      out.step_error[c] = std::sqrt(std::max(0.0, variance * inverse_normal(c, c))) / s;
    }
  }
  out.done = true;
  return out;
}

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
  void widen(double allowance) {
    if (!done) return;
    f_statistic = std::max(0.0, (reduction - allowance) / q) / ((rss - reduction) / d2);
    p_value = f_test_p_value(f_statistic, q, d2);
  }
};

ScoreTest score_test(const Setup& setup, const Model& candidate, const Fit& current,
                     const Eigen::VectorXd& neutral, const std::vector<Eigen::VectorXd>& weights,
                     double allowance) {
  ScoreTest out;
  const Eigen::Index p = current.theta.size();
  if (neutral.size() != candidate.forward->num_parameters() - p) return out;
  Eigen::VectorXd theta(candidate.forward->num_parameters());
  theta << current.theta, neutral;
  const NewColumnProjection projection =
      project_on_new_columns(setup, candidate, theta, p, weights, nullptr);
  if (!projection.done) return out;
  const int q = projection.rank;
  const int d2 = current.rows - static_cast<int>(p) - q;
  out.reduction = projection.residual;
  if (d2 <= 0 || !(projection.rss - out.reduction > 0.0)) return out;
  out.q = q, out.d2 = d2, out.rss = projection.rss;
  if (projection.step.size() == neutral.size()) {
    out.estimate = neutral + projection.step;
    out.estimate_error = projection.step_error;
  }
  out.done = true;
  out.widen(allowance);
  return out;
}

// The first expected value of `effect` (Effect::expected_values) that its estimated parameters
// contradict, as a note for the report; empty when every one is consistent or not estimable.
// Records the estimate in the candidate's test.
std::string contradicted_expectation(const Effect& effect, const Eigen::VectorXd& values,
                                     const Eigen::VectorXd& errors, const std::string& how,
                                     CandidateTest& test) {
  for (const ExpectedValue& expected : effect.expected_values()) {
    if (expected.index >= values.size() || expected.index >= errors.size()) continue;
    const double estimate = values[expected.index], error = errors[expected.index];
    if (!std::isfinite(estimate) || !std::isfinite(error)) continue;
    test.expected_parameter = effect.parameter_names()[static_cast<size_t>(expected.index)];
    test.expected_estimate = estimate;
    test.expected_error = error;
    if (std::abs(estimate - expected.value) <= expected.tolerance + 3.0 * error) continue;
    return "not added: " + how + " " + test.expected_parameter + " = " + std::to_string(estimate) +
           " +- " + std::to_string(error) + ", inconsistent with " +
           std::to_string(expected.value) + " (tolerance " + std::to_string(expected.tolerance) +
           " + 3 standard errors): " + expected.meaning;
  }
  return {};
}

ErrorSummary summarize(const std::vector<Eigen::Vector3d>& residuals, const std::vector<int>& rows,
                       int dim) {
  ErrorSummary s;
  double sum = 0.0;
  int count = 0;
  for (int m : rows) {
    for (int c = 0; c < dim; ++c) {
      const double r = residuals[static_cast<size_t>(m)][c];
      sum += r * r;
      s.max = std::max(s.max, std::abs(r));
      ++count;
    }
    s.max_norm = std::max(s.max_norm, residuals[static_cast<size_t>(m)].head(dim).norm());
  }
  s.rms = count > 0 ? std::sqrt(sum / count) : 0.0;
  return s;
}

// Model displacement at every marker for theta.
std::vector<Eigen::Vector3d> marker_predictions(const Setup& setup, const Model& model,
                                                const Eigen::VectorXd& theta, size_t markers) {
  const ModelEvaluation eval = model.forward->evaluate(theta, false);
  std::vector<Eigen::Vector3d> out(markers, Eigen::Vector3d::Zero());
  for (size_t l = 0; l < setup.markers.size(); ++l)
    for (size_t k = 0; k < setup.markers[l].size(); ++k)
      for (int c = 0; c < setup.dim; ++c)
        out[static_cast<size_t>(setup.markers[l][k])][c] =
            eval.predictions[l][static_cast<Eigen::Index>(k) * setup.dim + c];
  return out;
}

// The residual of the model at theta at every marker, and what the noise estimate groups it by.
struct MarkerResidual {
  std::vector<Eigen::Vector3d> predicted, residual, positions;
  std::vector<int> group;  // load case index
};

MarkerResidual marker_residual(const Setup& setup, const Model& model, const Eigen::VectorXd& theta,
                               const std::vector<Marker>& markers) {
  MarkerResidual r;
  r.predicted = marker_predictions(setup, model, theta, markers.size());
  r.residual.resize(markers.size());
  r.positions.resize(markers.size());
  r.group.resize(markers.size());
  for (size_t m = 0; m < markers.size(); ++m) {
    r.residual[m] = markers[m].displacement - r.predicted[m];
    r.positions[m] = markers[m].position;
    r.group[m] = setup.case_index.at(markers[m].load_case);
  }
  return r;
}

// Validates the inputs and builds everything that stays fixed while effects come and go.
void make_setup(Setup& setup, const analysis::Problem& problem, const std::vector<Marker>& markers,
                const std::vector<MarkerPlacement>& placements, bool fit_poisson,
                const std::function<void(const std::string&)>& say) {
  analysis::validate_problem(problem);
  if (markers.empty()) throw nurbs::InputError("measurements: no markers to fit");
  if (placements.size() != markers.size())
    throw std::invalid_argument("identify: one placement per marker expected");

  setup.problem = &problem;
  setup.dofs = analysis::DofMap(problem);
  setup.constraints = analysis::build_constraints(problem, setup.dofs);
  setup.dim = setup.dofs.dofs_per_node();
  setup.material_parameters = fit_poisson ? 2 : 1;
  const int dim = setup.dim;
  if (say) say("assembling the stiffness (" + std::to_string(setup.dofs.num_dofs()) + " DOFs)");
  setup.lame = assemble_lame_stiffness(problem, setup.dofs);

  // Markers grouped by load case; observation operators from the NURBS basis at each marker.
  std::map<std::string, int> case_index;
  for (size_t l = 0; l < problem.load_cases.size(); ++l)
    case_index[problem.load_cases[l].id] = static_cast<int>(l);
  const size_t num_cases = problem.load_cases.size();
  setup.case_index = case_index;
  setup.markers.resize(num_cases);
  for (size_t m = 0; m < markers.size(); ++m) {
    const auto it = case_index.find(markers[m].load_case);
    if (it == case_index.end())
      throw nurbs::InputError("measurements: row " + std::to_string(markers[m].row) +
                              ": load case \"" + markers[m].load_case +
                              "\" is not in the case file; use one of its load_cases ids");
    setup.markers[static_cast<size_t>(it->second)].push_back(static_cast<int>(m));
  }
  setup.context.marker_positions.resize(num_cases);
  for (size_t l = 0; l < num_cases; ++l) {
    const auto& ids = setup.markers[l];
    const Eigen::Index rows = static_cast<Eigen::Index>(ids.size()) * dim;
    std::vector<Eigen::Triplet<double>> triplets;
    Eigen::VectorXd measured(rows), sigma(rows);
    for (size_t k = 0; k < ids.size(); ++k) {
      const Marker& marker = markers[static_cast<size_t>(ids[k])];
      const MarkerPlacement& place = placements[static_cast<size_t>(ids[k])];
      const nurbs::RationalBasis basis =
          problem.patches[static_cast<size_t>(place.patch)].basis(place.param, 0);
      for (int c = 0; c < dim; ++c) {
        const Eigen::Index row = static_cast<Eigen::Index>(k) * dim + c;
        for (size_t a = 0; a < basis.indices.size(); ++a)
          triplets.emplace_back(row, setup.dofs.dof(place.patch, basis.indices[a], c),
                                basis.values[static_cast<Eigen::Index>(a)]);
        measured[row] = marker.displacement[c];
        sigma[row] = marker.sigma;
      }
      setup.context.marker_positions[l].push_back(marker.position);
    }
    Observation obs;
    obs.operator_.resize(rows, setup.dofs.num_dofs());
    obs.operator_.setFromTriplets(triplets.begin(), triplets.end());
    setup.observations.push_back(std::move(obs));
    setup.measured.push_back(measured);
    setup.sigma.push_back(sigma);
    setup.nominal_loads.push_back(
        analysis::assemble_load(problem, setup.dofs, problem.load_cases[l]));
  }

  // Effect context: model size, material coefficients.
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const auto& patch : problem.patches)
    for (const auto& x : patch.control_points()) {
      lo = lo.cwiseMin(x);
      hi = hi.cwiseMax(x);
    }
  EffectContext& context = setup.context;
  context.problem = &problem;
  context.dofs = &setup.dofs;
  context.constraints = &setup.constraints;
  context.stiffness = &setup.lame;
  context.dimension = dim;
  context.centre = 0.5 * (lo + hi);
  context.length = (hi - lo).norm();
  context.youngs_modulus_prior = problem.material.youngs_modulus;
  const int nu_index = fit_poisson ? 1 : -1;
  context.lambda = lame_coefficient(true, problem.formulation, problem.material.youngs_modulus,
                                    problem.material.poisson_ratio, nu_index);
  context.mu = lame_coefficient(false, problem.formulation, problem.material.youngs_modulus,
                                problem.material.poisson_ratio, nu_index);
}

}  // namespace

IdentifyResult identify(const analysis::Problem& problem, const std::vector<Marker>& markers,
                        const std::vector<MarkerPlacement>& placements,
                        const IdentifyOptions& options) {
  const auto start_time = std::chrono::steady_clock::now();
  const QuietSolverWarnings quiet;
  auto say = [&](const std::string& message) {
    if (options.progress) options.progress(message);
  };
  // The case's discretisation first: the nominal fit there gives the material and the noise
  // level that the discretisation check compares the reference's own error with.
  Setup case_setup;
  make_setup(case_setup, problem, markers, placements, options.fit_poisson, say);
  const int element_threads = options.threads > 0 ? options.threads : omp_get_max_threads();
  case_setup.context.threads = element_threads;
  case_setup.component_weight = component_weights(options, markers, case_setup.dim);
  IdentifyResult result;
  const std::vector<bool> all_markers(markers.size(), true);
  std::vector<int> all_rows(markers.size());
  for (size_t m = 0; m < markers.size(); ++m) all_rows[m] = static_cast<int>(m);

  // Baseline fit. A provisional noise level makes the residuals O(1) for the solver's tolerances;
  // uniform weights do not change the estimate.
  double rms_data = 0.0;
  for (const auto& m : case_setup.measured) rms_data += m.squaredNorm();
  int total_rows = 0;
  for (const auto& m : case_setup.measured) total_rows += static_cast<int>(m.size());
  rms_data = std::sqrt(rms_data / std::max(1, total_rows));
  const double provisional =
      options.noise_sigma > 0.0 ? options.noise_sigma : std::max(1e-3 * rms_data, 1e-300);
  auto nominal_fit = [&](const Setup& s, const Model& nominal) {
    const Fit fit = run_fit(s, nominal, make_weights(s, provisional, all_markers));
    if (!fit.ok) throw std::runtime_error("the nominal model's fit failed: " + fit.message);
    return fit;
  };
  say("fitting the nominal model");
  const Model case_baseline = build_model(case_setup, {}, Eigen::VectorXd());
  const Fit case_fit = nominal_fit(case_setup, case_baseline);

  // Discretisation control before diagnosis.
  std::optional<analysis::Problem> refined_problem;
  std::unique_ptr<Setup> refined_setup;
  if (options.discretization.enabled) {
    double noise = options.noise_sigma;
    if (!(noise > 0.0)) {  // per-marker sigmas, else the data's own estimate
      double sum = 0.0;
      int given = 0;
      for (const Marker& marker : markers)
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
          marker_residual(case_setup, case_baseline, case_fit.theta, markers);
      noise = weighted_noise(case_setup, case_residual.positions, case_residual.residual,
                             case_residual.group);
    }
    if (!(noise > 0.0)) noise = provisional;
    // The reference must be accurate enough for the most precise component (sigma / max w_c).
    noise /= max_weight;
    const double nu = options.fit_poisson ? case_fit.theta[1] : problem.material.poisson_ratio;
    const double youngs_modulus = problem.material.youngs_modulus * case_fit.theta[0];
    result.discretization = check_discretization(problem, markers, placements, youngs_modulus, nu,
                                                 noise, options.discretization, say);
    if (result.discretization.chosen_problem) {
      refined_problem = std::move(result.discretization.chosen_problem);
      result.discretization.chosen_problem.reset();
      refined_setup = std::make_unique<Setup>();
      make_setup(*refined_setup, *refined_problem, markers, placements, options.fit_poisson, say);
      refined_setup->context.threads = element_threads;
      refined_setup->component_weight = case_setup.component_weight;
    }
  } else {
    result.discretization.note = "turned off";
  }
  Setup& setup = refined_setup ? *refined_setup : case_setup;
  // The loop factorises models of a few thousand DOFs many times: one thread. CHOLMOD's OpenMP
  // workers gain little at this size and spin between calls (measured: 22 % of the CPU time of
  // a 3D run went to spinning workers on a loaded 2-core machine).
  const analysis::ThreadScope single_thread(1);
  const int dim = setup.dim;
  const size_t num_cases = problem.load_cases.size();
  EffectContext& context = setup.context;

  std::optional<Model> refined_baseline;
  if (refined_setup) refined_baseline = build_model(setup, {}, Eigen::VectorXd());
  const Model& baseline = refined_baseline ? *refined_baseline : case_baseline;
  const Fit first_fit = refined_setup ? nominal_fit(setup, baseline) : case_fit;
  const MarkerResidual nominal = marker_residual(setup, baseline, first_fit.theta, markers);
  result.model_before = nominal.predicted;
  const std::vector<Eigen::Vector3d>& residual_before = nominal.residual;
  const std::vector<Eigen::Vector3d>& positions = nominal.positions;
  const std::vector<int>& group = nominal.group;
  result.before = summarize(residual_before, all_rows, dim);
  std::vector<std::string> case_ids;
  for (const auto& load : problem.load_cases) case_ids.push_back(load.id);
  auto describe = [&](const std::vector<Eigen::Vector3d>& residual) {
    return describe_residual(positions, residual, group, case_ids, setup.nominal_loads, dim,
                             context.centre, context.length);
  };
  result.residual_before = describe(residual_before);
  result.noise_given = options.noise_sigma > 0.0;
  result.noise_estimate = result.noise_given
                              ? options.noise_sigma
                              : weighted_noise(setup, positions, residual_before, group);
  if (!(result.noise_estimate > 0.0)) result.noise_estimate = provisional;
  std::vector<Eigen::VectorXd> weights = make_weights(setup, result.noise_estimate, all_markers);

  // Widening when the reference could not be made accurate enough: the weighted squared
  // discretisation error at the markers, less the part a refit of E absorbs (a common scale of
  // the nominal predictions), is what an effect could explain without being physical.
  const DiscretizationCheck& disc = result.discretization;
  if (disc.done && !disc.within_target && disc.marker_error.size() == markers.size()) {
    double ee = 0.0, eu = 0.0, uu = 0.0;
    for (size_t l = 0; l < setup.markers.size(); ++l)
      for (size_t k = 0; k < setup.markers[l].size(); ++k)
        for (int c = 0; c < dim; ++c) {
          const auto m = static_cast<size_t>(setup.markers[l][k]);
          const double w = weights[l][static_cast<Eigen::Index>(k) * dim + c];
          const double e = w * disc.marker_error[m][c], u = w * result.model_before[m][c];
          ee += e * e, eu += e * u, uu += u * u;
        }
    result.discretization_allowance = std::max(0.0, uu > 0.0 ? ee - eu * eu / uu : ee);
    say("the reference's discretisation error exceeds a third of the noise within the DOF "
        "budget; every F-test is widened by it (weighted RSS " +
        std::to_string(result.discretization_allowance) + ")");
  }
  const double allowance = result.discretization_allowance;

  // Candidates (matrices assembled once).
  std::vector<std::string> names = options.candidates ? *options.candidates : effect_names();
  std::vector<std::unique_ptr<Effect>> library;
  std::vector<std::string> unavailable;
  for (const std::string& name : names) {
    std::string why;
    auto effect = make_effect(name, context, &why);
    if (effect)
      library.push_back(std::move(effect));
    else
      unavailable.push_back(name + ": " + why);
  }

  // The model's own error at the observations (per load case, rows as measured): the
  // discretisation check's estimate at the level used. Whatever part of it a candidate could
  // absorb is not evidence for that candidate: its F-test is widened by it (below).
  std::vector<Eigen::VectorXd> model_error;
  if (disc.done && disc.marker_error.size() == markers.size())
    for (size_t l = 0; l < setup.measured.size(); ++l) {
      Eigen::VectorXd e(setup.measured[l].size());
      for (Eigen::Index k = 0; k < e.size(); ++k)
        e[k] =
            disc.marker_error[static_cast<size_t>(setup.markers[l][static_cast<size_t>(k / dim)])]
                             [k % dim];
      model_error.push_back(e);
    }
  // Allowance of each effect, from the round that added it (for the backward step).
  std::map<const Effect*, double> allowance_of;

  // The fits of the linear models tried so far, by their effects (in order), all under the
  // selection's weights. The backward step and the swap stage try models fitted before (one
  // effect replacing the first chosen is a model of round 1): a refit would repeat the fit
  // (measured on the suite's tube_graded: 6 s for one support_compliance refit).
  std::map<std::vector<const Effect*>, Fit> linear_fits;
  // The fit of the model with `effects` from `start`: the one made before, else a new one (kept
  // when the model is linear); nullopt for a large-deformation model when `newton` is false.
  auto fit_of = [&](const std::vector<const Effect*>& effects, const Eigen::VectorXd& start,
                    FitStart how, bool newton) -> std::optional<Fit> {
    if (const auto known = linear_fits.find(effects); known != linear_fits.end())
      return known->second;
    const Model model = build_model(setup, effects, start);
    if (model.forward->nonlinear() && !newton) return std::nullopt;
    const Fit fit = run_fit(setup, model, weights, nullptr, how);
    if (fit.ok && !model.forward->nonlinear()) linear_fits[effects] = fit;
    return fit;
  };

  // Forward selection.
  std::vector<const Effect*> chosen;
  Model current = build_model(setup, chosen, first_fit.theta);
  Fit current_fit = run_fit(setup, current, weights);
  const int p_before = static_cast<int>(current_fit.theta.size());
  // Each effect can be added at most twice (once more after a backward step dropped it).
  const size_t max_rounds = 2 * library.size() + 1;
  while (static_cast<int>(chosen.size()) < options.max_effects &&
         result.rounds.size() < max_rounds) {
    SelectionRound round;
    round.rss = current_fit.rss;
    {
      const auto predicted = marker_predictions(setup, current, current_fit.theta, markers.size());
      std::vector<Eigen::Vector3d> residual(markers.size());
      for (size_t m = 0; m < markers.size(); ++m)
        residual[m] = markers[m].displacement - predicted[m];
      round.residual = describe(residual);
    }
    for (const std::string& note : unavailable) {
      CandidateTest test;
      test.effect = note.substr(0, note.find(':'));
      test.note = note.substr(note.find(':') + 2);
      round.candidates.push_back(test);
    }
    int tried = 0;
    double best_p = 2.0, best_bic = 0.0;
    const Effect* best = nullptr;
    Fit best_fit;
    // The expensive candidates last, so that the linear ones' best improvement is known when
    // their score test is read.
    std::vector<const Effect*> order;
    for (const auto& effect : library)
      if (!effect->expensive()) order.push_back(effect.get());
    for (const auto& effect : library)
      if (effect->expensive()) order.push_back(effect.get());
    for (const Effect* effect : order) {
      if (std::find(chosen.begin(), chosen.end(), effect) != chosen.end()) continue;
      std::vector<const Effect*> trial = chosen;
      trial.push_back(effect);
      const Model model = build_model(setup, trial, current_fit.theta);
      say("trying " + effect->name());
      const auto fit_start = std::chrono::steady_clock::now();
      CandidateTest test;
      test.effect = effect->name();
      test.parameters = effect->num_parameters();
      ++tried;
      // Every candidate is fitted only when a score test at the current fit does not rule it
      // out: far below the threshold it cannot become significant. The test costs one
      // evaluation of the candidate's model, a fit many: a Newton solve each for the
      // large-deformation candidate, a factorisation each once a stiffness gradient or a
      // compliant support is in the model (measured on the suite's tube_graded: round 2's
      // refits took 63 of 164 s).
      const Eigen::VectorXd screening = effect->screening_values();
      const bool screen = screening.size() == effect->num_parameters();
      ScoreTest score;
      if (screen) score = score_test(setup, model, current_fit, screening, weights, allowance);
      if (screen) {
        const double threshold = options.significance / static_cast<double>(library.size());
        if (score.done) test.score_f = score.f_statistic;
        if (score.done && score.p_value > 10.0 * threshold) {
          test.f_statistic = score.f_statistic;
          test.p_value = score.p_value;
          test.rss = current_fit.rss - score.reduction;
          test.note = "screened out by a score test at the current fit (F = " +
                      std::to_string(score.f_statistic) + ", p = " + std::to_string(score.p_value) +
                      "; fitted only when p < 10 x the threshold)";
          test.seconds =
              std::chrono::duration<double>(std::chrono::steady_clock::now() - fit_start).count();
          round.candidates.push_back(test);
          continue;
        }
        // An effect whose physics fixes a parameter must find it near that value: its one-step
        // estimate from the score test is exact for a parameter the prediction is linear in
        // (the nonlinear blend weight), to first order in the others.
        if (score.done) {
          const std::string contradiction =
              contradicted_expectation(*effect, score.estimate, score.estimate_error,
                                       "the score test's one-step estimate", test);
          if (!contradiction.empty()) {
            test.f_statistic = score.f_statistic;
            test.p_value = score.p_value;
            test.rss = current_fit.rss - score.reduction;
            test.note = contradiction;
            test.seconds =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - fit_start).count();
            round.candidates.push_back(test);
            continue;
          }
        }
        // Significant, but explaining far less than a candidate already fitted this round: it
        // cannot be this round's choice (the score test's reduction is the first-order estimate
        // of its fit's, 10x below the best); the next round screens it again.
        const double best_reduction = best ? current_fit.rss - best_fit.rss : 0.0;
        if (score.done && best && best_p < threshold && score.reduction < 0.1 * best_reduction) {
          test.f_statistic = score.f_statistic;
          test.p_value = score.p_value;
          test.rss = current_fit.rss - score.reduction;
          test.note = "deferred: a score test at the current fit estimates an RSS reduction of " +
                      std::to_string(score.reduction) + ", below a tenth of " + best->name() +
                      "'s " + std::to_string(best_reduction) + "; screened again next round";
          test.seconds =
              std::chrono::duration<double>(std::chrono::steady_clock::now() - fit_start).count();
          round.candidates.push_back(test);
          continue;
        }
      }
      const bool check_expectations = !effect->expected_values().empty();
      Eigen::MatrixXd covariance;
      const Fit fit = run_fit(setup, model, weights, check_expectations ? &covariance : nullptr,
                              FitStart::kNewParameters);
      if (fit.ok && !model.forward->nonlinear()) linear_fits[trial] = fit;
      test.seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - fit_start).count();
      if (!fit.ok) {
        test.note = "fit failed: " + fit.message;
        round.candidates.push_back(test);
        continue;
      }
      std::string contradiction;
      if (check_expectations && covariance.rows() == fit.theta.size()) {
        const Eigen::Index k = effect->num_parameters();
        const Eigen::VectorXd errors =
            covariance.diagonal().tail(k).cwiseMax(0.0).cwiseSqrt() *
            std::sqrt(fit.rss / std::max(1.0, static_cast<double>(fit.rows - fit.theta.size())));
        contradiction =
            contradicted_expectation(*effect, fit.theta.tail(k), errors, "the fitted", test);
      }
      // The part of the model's own discretisation error this candidate could absorb, |P e|^2,
      // to first order at its fit, plus two standard deviations of its cross term with the
      // noise, 2 x 2|P e|: the candidate must explain more than that to count (measured on the
      // suite's cantilever_frame: the Newton candidate gained 12 weighted RSS units, p = 5e-4,
      // where the estimated discretisation error at the markers was 25).
      double candidate_allowance = allowance;
      if (!model_error.empty()) {
        const double absorbed =
            project_on_new_columns(setup, model, fit.theta, current_fit.theta.size(), weights,
                                   &model_error)
                .model_error;
        candidate_allowance = std::max(allowance, absorbed + 4.0 * std::sqrt(absorbed));
      }
      test.model_error_allowance = candidate_allowance;
      allowance_of[effect] = candidate_allowance;
      test.rss = fit.rss;
      const int d1 = test.parameters;
      const int d2 = fit.rows - static_cast<int>(fit.theta.size());
      test.f_statistic =
          d2 > 0 ? std::max(0.0, (current_fit.rss - fit.rss - candidate_allowance) / d1) /
                       (fit.rss / d2)
                 : 0.0;
      test.p_value = f_test_p_value(test.f_statistic, d1, d2);
      const double n = static_cast<double>(fit.rows);
      test.delta_bic =
          n * std::log(std::max(fit.rss + candidate_allowance, 1e-300) / current_fit.rss) +
          d1 * std::log(n);
      // Both criteria must favour an effect: the F-test at a fixed significance lets ever
      // smaller systematic misfits through as the number of markers grows, BIC's penalty
      // (ln n per parameter) does not (measured on the suite's tube with undeclared self-weight:
      // a clamp compliance passed the F-test, p = 8e-4, with delta BIC +0.6).
      const bool bic_favours = !(test.delta_bic >= 0.0);
      if (!bic_favours && test.p_value < options.significance)
        test.note = "significant by the F-test, but BIC does not favour it (delta BIC " +
                    std::to_string(test.delta_bic) + " >= 0): not added";
      if (!contradiction.empty()) test.note = contradiction;
      round.candidates.push_back(test);
      // Strong effects have p-values that underflow to 0 in double; among equal p-values the
      // candidate with the lower BIC wins (the most explained per parameter), not the first one
      // tried and not simply the largest.
      if (bic_favours && contradiction.empty() &&
          (test.p_value < best_p ||
           (test.p_value == best_p && best && test.delta_bic < best_bic))) {
        best_p = test.p_value;
        best_bic = test.delta_bic;
        best = effect;
        best_fit = fit;
      }
    }
    if (best && best_p < options.significance / std::max(1, tried)) {
      round.added = best->name();
      chosen.push_back(best);
      say("added " + best->name() + " (p = " + std::to_string(best_p) + ")");
      current = build_model(setup, chosen, best_fit.theta);
      current_fit = best_fit;
      // Backward step (stepwise selection): an effect added earlier may only have stood in for
      // the new one, and an effect may be more general than the data need now (a rigid motion
      // per load case where one shared motion does). Drop an earlier effect, or replace an
      // effect by its nested simpler version (Effect::simpler), while the F-test of the change
      // fails or BIC favours the change; the least significant change first.
      while (true) {
        double worst_p = -1.0;
        bool worst_favoured_by_bic = false;
        std::vector<const Effect*> worst_effects;
        Fit worst_fit;
        std::string worst_change;   // for the progress line
        std::string worst_removed;  // for round.removed: the effect's name, or the replacement
        auto consider = [&](const std::vector<const Effect*>& reduced, const Eigen::VectorXd& start,
                            int d1, const std::string& change, const std::string& removed,
                            double effect_allowance) {
          if (d1 <= 0) return;
          const Fit fit = *fit_of(reduced, start, FitStart::kNearOptimum, true);
          if (!fit.ok) return;
          const int d2 = current_fit.rows - static_cast<int>(current_fit.theta.size());
          const double f = std::max(0.0, (fit.rss - current_fit.rss - effect_allowance) / d1) /
                           (current_fit.rss / d2);
          const double p = f_test_p_value(f, d1, d2);
          const double n = static_cast<double>(current_fit.rows);
          const double delta_bic =
              n * std::log(fit.rss / std::max(current_fit.rss + effect_allowance, 1e-300)) -
              d1 * std::log(n);
          const bool droppable = p > options.significance || delta_bic < 0.0;
          if (droppable && p > worst_p) {
            worst_p = p;
            worst_favoured_by_bic = delta_bic < 0.0;
            worst_effects = reduced;
            worst_fit = fit;
            worst_change = change;
            worst_removed = removed;
          }
        };
        for (size_t e = 0; e < chosen.size(); ++e) {
          if (e + 1 < chosen.size() && chosen.size() > 1) {  // not the effect just added
            std::vector<const Effect*> reduced = chosen;
            reduced.erase(reduced.begin() + static_cast<std::ptrdiff_t>(e));
            consider(reduced, start_replacing(setup, current, current_fit.theta, e, nullptr),
                     chosen[e]->num_parameters(), "dropped " + chosen[e]->name(), chosen[e]->name(),
                     allowance_of[chosen[e]]);
          }
          const std::string simpler = chosen[e]->simpler();
          const auto it = std::find_if(library.begin(), library.end(),
                                       [&](const auto& x) { return x->name() == simpler; });
          if (!simpler.empty() && it != library.end() &&
              std::find(chosen.begin(), chosen.end(), it->get()) == chosen.end()) {
            std::vector<const Effect*> replaced = chosen;
            replaced[e] = it->get();
            const std::string change = "replaced " + chosen[e]->name() + " by " + simpler;
            consider(replaced, start_replacing(setup, current, current_fit.theta, e, it->get()),
                     chosen[e]->num_parameters() - (*it)->num_parameters(), change, change,
                     allowance_of[chosen[e]]);
          }
        }
        if (worst_p < 0.0) break;  // no change is favoured by either criterion
        say(worst_change + " (p = " + std::to_string(worst_p) +
            (worst_favoured_by_bic ? ", BIC favours the change)" : ")"));
        round.removed.push_back(worst_removed);
        chosen = worst_effects;
        current = build_model(setup, chosen, worst_fit.theta);
        current_fit = worst_fit;
      }
      result.rounds.push_back(round);
    } else {
      result.rounds.push_back(round);
      break;
    }
  }

  // Swap stage. Forward selection is path dependent: an effect that explains a bit of
  // everything (a rigid motion per load case) can win the first round and leave nothing for the
  // physical effect that explains the same data with fewer parameters (a stiff clamp, whose
  // motion is fixed by its two spring stiffnesses). Each selected effect is replaced in turn by
  // every other linear candidate and the models compared by BIC (not nested: no F-test). A swap
  // with delta BIC < -2 (positive evidence) is taken, and the stage repeats; alternatives within
  // 2 of the selection are reported as indistinguishable on these data.
  {
    const double n = static_cast<double>(current_fit.rows);
    auto bic = [&](const Fit& f) {
      return n * std::log(std::max(f.rss, 1e-300)) +
             static_cast<double>(f.theta.size()) * std::log(n);
    };
    for (size_t pass = 0; pass < library.size() && !chosen.empty(); ++pass) {
      std::vector<Alternative> seen;
      double best_delta = -2.0;
      std::vector<const Effect*> best_effects;
      Fit best_alternative;
      Alternative best_swap;
      for (size_t e = 0; e < chosen.size(); ++e)
        for (const auto& candidate : library) {
          if (std::find(chosen.begin(), chosen.end(), candidate.get()) != chosen.end()) continue;
          std::vector<const Effect*> swapped = chosen;
          swapped[e] = candidate.get();
          // Not large-deformation models (Newton fits): the score test handled them.
          const std::optional<Fit> swap_fit = fit_of(
              swapped, start_replacing(setup, current, current_fit.theta, e, candidate.get()),
              FitStart::kNewParameters, false);
          if (!swap_fit || !swap_fit->ok) continue;
          const Fit& fit = *swap_fit;
          const Alternative alternative{chosen[e]->name(), candidate->name(),
                                        bic(fit) - bic(current_fit), false};
          seen.push_back(alternative);
          if (alternative.delta_bic < best_delta) {
            best_delta = alternative.delta_bic;
            best_effects = swapped;
            best_alternative = fit;
            best_swap = alternative;
          }
        }
      if (best_effects.empty()) {
        for (const Alternative& a : seen)
          if (std::abs(a.delta_bic) < 2.0) result.alternatives.push_back(a);
        break;
      }
      best_swap.swapped = true;
      result.alternatives.push_back(best_swap);
      say("swapped " + best_swap.replaced + " for " + best_swap.by +
          " (delta BIC = " + std::to_string(best_swap.delta_bic) + ")");
      chosen = best_effects;
      current = build_model(setup, chosen, best_alternative.theta);
      current_fit = best_alternative;
    }
  }

  // Without a given noise level, re-estimate it from the final residual: the baseline residual's
  // smooth misfit leaks into neighbour differences when markers are coarse.
  if (!result.noise_given) {
    const auto predicted = marker_predictions(setup, current, current_fit.theta, markers.size());
    std::vector<Eigen::Vector3d> residual(markers.size());
    for (size_t m = 0; m < markers.size(); ++m)
      residual[m] = markers[m].displacement - predicted[m];
    const double sigma = weighted_noise(setup, positions, residual, group);
    if (sigma > 0.0) result.noise_estimate = sigma;
  }
  const std::vector<Eigen::VectorXd> selection_weights = weights;
  weights = make_weights(setup, result.noise_estimate, all_markers);
  // The nominal model's fit under the final weights: first_fit when they only rescale its own.
  Eigen::MatrixXd cov_before;
  const Model nominal_model = build_model(setup, {}, first_fit.theta);
  const std::optional<Fit> nominal_reweighted =
      reweighted(first_fit, make_weights(setup, provisional, all_markers), weights);
  const Fit baseline_final =
      nominal_reweighted ? *nominal_reweighted : run_fit(setup, nominal_model, weights);
  if (baseline_final.ok) cov_before = fit_covariance(nominal_model, baseline_final.theta, weights);
  const double rss_before = baseline_final.rss;
  if (baseline_final.ok) {
    const double e_prior = problem.material.youngs_modulus;
    const Eigen::VectorXd& t = baseline_final.theta;
    result.parameters_before.push_back(
        {"material", "E", "Pa", e_prior * t[0], e_prior * std::sqrt(cov_before(0, 0))});
    if (options.fit_poisson)
      result.parameters_before.push_back(
          {"material", "nu", "1", t[1], std::sqrt(cov_before(1, 1))});
  }

  // Final fit with covariance.
  // (The selection's fits were made under the weights of the first noise estimate; the
  // re-estimate rescales them, which leaves the optimum where it is.)
  Eigen::MatrixXd cov;
  if (const std::optional<Fit> same = reweighted(current_fit, selection_weights, weights)) {
    current_fit = *same;
    cov = fit_covariance(current, current_fit.theta, weights);
  } else {
    current_fit = run_fit(setup, current, weights, &cov);
  }
  if (!current_fit.ok) throw std::runtime_error("the final fit failed: " + current_fit.message);
  const Eigen::VectorXd& theta = current_fit.theta;
  auto se = [&](int k) { return std::sqrt(cov(k, k)); };
  const double e_prior = problem.material.youngs_modulus;
  result.parameters.push_back({"material", "E", "Pa", e_prior * theta[0], e_prior * se(0)});
  result.youngs_modulus = e_prior * theta[0];
  result.poisson_ratio = problem.material.poisson_ratio;
  if (options.fit_poisson) {
    result.parameters.push_back({"material", "nu", "1", theta[1], se(1)});
    result.poisson_ratio = theta[1];
  }
  for (size_t e = 0; e < chosen.size(); ++e) {
    const auto [first, count] = current.blocks[e];
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
  for (int c = 0; c < setup.dim; ++c) result.component_weights.push_back(setup.component_weight[c]);
  result.model_after = marker_predictions(setup, current, theta, markers.size());
  result.corrected_displacements = current.forward->evaluate(theta, false).displacements;
  if (refined_setup) {
    // The corrected reference on the case's own DOFs (the spring model's net): the same effects
    // built on the case's discretisation, evaluated at the identified parameters.
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
    result.corrected_displacements = case_model.forward->evaluate(theta, false).displacements;
  }
  std::vector<Eigen::Vector3d> residual_after(markers.size());
  for (size_t m = 0; m < markers.size(); ++m)
    residual_after[m] = markers[m].displacement - result.model_after[m];
  result.after = summarize(residual_after, all_rows, dim);
  result.residual_after = describe(residual_after);
  result.observations = current_fit.rows;
  // Chi-square per degree of freedom against the noise level (weights are 1/sigma).
  result.chi2_before = rss_before / std::max(1, current_fit.rows - p_before);
  result.chi2_after =
      current_fit.rss / std::max(1, current_fit.rows - static_cast<int>(theta.size()));
  for (size_t l = 0; l < num_cases; ++l) {
    LoadCaseErrors errors;
    errors.id = problem.load_cases[l].id;
    errors.markers = static_cast<int>(setup.markers[l].size());
    errors.before = summarize(residual_before, setup.markers[l], dim);
    errors.after = summarize(residual_after, setup.markers[l], dim);
    result.load_cases.push_back(errors);
  }

  // Hold-out folds, independent refits: fit on the even markers of every load case and validate
  // on the odd ones (fold 0), and leave one load case out (folds 1..). They run on the machine's
  // cores, each with a factorisation cache of its own (they differ in their weights, so one
  // shared cache would serialise them and factorise at every switch). Measured on the suite's
  // tube_graded (5,832 DOFs, a factorisation per evaluation): 19 s one after the other.
  const bool leave_cases_out = options.holdout && num_cases >= 2;
  const int folds = options.holdout ? 1 + (leave_cases_out ? static_cast<int>(num_cases) : 0) : 0;
  std::vector<std::optional<LoadCaseHoldout>> case_folds(num_cases);
  std::vector<std::exception_ptr> fold_errors(static_cast<size_t>(folds));
  // Each fold's cache starts with the loop's large-deformation solutions (Newton's starts).
  std::vector<std::shared_ptr<FactorizationCache>> fold_caches;
  for (int f = 0; f < folds; ++f) {
    fold_caches.push_back(make_factorization_cache());
    fold_caches.back()->nonlinear_starts = setup.factorizations->nonlinear_starts;
    fold_caches.back()->linear_starts = setup.factorizations->linear_starts;
  }
  auto markers_fold = [&] {
    std::vector<bool> fit_marker(markers.size(), false);
    std::vector<int> validation;
    for (const auto& ids : setup.markers)
      for (size_t k = 0; k < ids.size(); ++k) {
        if (k % 2 == 0)
          fit_marker[static_cast<size_t>(ids[k])] = true;
        else
          validation.push_back(ids[k]);
      }
    const auto holdout_weights = make_weights(setup, result.noise_estimate, fit_marker);
    const auto& cache = fold_caches[0];
    const Model base = build_model(setup, {}, first_fit.theta, cache);
    const Fit base_fit = run_fit(setup, base, holdout_weights);
    const Model full = build_model(setup, chosen, theta, cache);
    const Fit full_fit = run_fit(setup, full, holdout_weights);
    if (base_fit.ok && full_fit.ok && !validation.empty()) {
      auto residuals = [&](const Model& model, const Fit& fit) {
        const auto predicted = marker_predictions(setup, model, fit.theta, markers.size());
        std::vector<Eigen::Vector3d> r(markers.size());
        for (size_t m = 0; m < markers.size(); ++m) r[m] = markers[m].displacement - predicted[m];
        return r;
      };
      result.holdout.fit_markers = static_cast<int>(markers.size() - validation.size());
      result.holdout.validation_markers = static_cast<int>(validation.size());
      result.holdout.validation_before = summarize(residuals(base, base_fit), validation, dim);
      result.holdout.validation_after = summarize(residuals(full, full_fit), validation, dim);
      result.holdout_done = true;
    }
  };
  // Leave load case l out: do the effects predict a load case they were not fitted to?
  auto case_fold = [&](size_t l) {
    std::vector<bool> fit_marker(markers.size(), true);
    for (int m : setup.markers[l]) fit_marker[static_cast<size_t>(m)] = false;
    const auto w = make_weights(setup, result.noise_estimate, fit_marker);
    const auto& cache = fold_caches[l + 1];
    LoadCaseHoldout out;
    out.id = problem.load_cases[l].id;
    out.markers = static_cast<int>(setup.markers[l].size());
    for (const bool final_model : {false, true}) {
      const Model model = final_model ? build_model(setup, chosen, theta, cache)
                                      : build_model(setup, {}, first_fit.theta, cache);
      const Fit fit = run_fit(setup, model, w);
      if (!fit.ok) return;
      const ModelEvaluation eval = model.forward->evaluate(fit.theta, true);
      // Columns that vanish on every other load case act on load case l alone.
      std::vector<Eigen::Index> local;
      for (Eigen::Index k = 0; k < fit.theta.size(); ++k) {
        double elsewhere = 0.0;
        for (size_t o = 0; o < num_cases; ++o)
          if (o != l) elsewhere += eval.jacobians[o].col(k).squaredNorm();
        if (elsewhere == 0.0 && eval.jacobians[l].col(k).squaredNorm() > 0.0) local.push_back(k);
      }
      Eigen::VectorXd r = setup.measured[l] - eval.predictions[l];
      if (!local.empty()) {
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
      }
      std::vector<Eigen::Vector3d> residual(markers.size(), Eigen::Vector3d::Zero());
      for (size_t k = 0; k < setup.markers[l].size(); ++k)
        for (int c = 0; c < dim; ++c)
          residual[static_cast<size_t>(setup.markers[l][k])][c] =
              r[static_cast<Eigen::Index>(k) * dim + c];
      (final_model ? out.after : out.before) = summarize(residual, setup.markers[l], dim);
      if (final_model) out.local_parameters = static_cast<int>(local.size());
    }
    case_folds[l] = out;
  };
  if (folds > 0) say("hold-out checks (" + std::to_string(folds) + " refits of two models)");
    // Nested OpenMP is off: the folds' own solves run on one thread each, as in the loop.
#pragma omp parallel for schedule(dynamic) \
    num_threads(std::max(1, std::min(element_threads, folds)))
  for (int f = 0; f < folds; ++f) {
    try {
      if (f == 0)
        markers_fold();
      else
        case_fold(static_cast<size_t>(f - 1));
    } catch (...) {
      fold_errors[static_cast<size_t>(f)] = std::current_exception();
    }
  }
  for (const auto& error : fold_errors)
    if (error) std::rethrow_exception(error);
  for (const auto& fold : case_folds)
    if (fold) result.load_case_holdout.push_back(*fold);
  // Last: the refined setup points into refined_problem until here.
  if (refined_problem) result.discretization.chosen_problem = std::move(refined_problem);
  result.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count();
  return result;
}

}  // namespace isospring::fitting

namespace isospring::fitting {

std::vector<Eigen::Vector3d> simulate_markers(
    const analysis::Problem& problem, const std::vector<Marker>& markers,
    const std::vector<MarkerPlacement>& placements,
    const std::vector<std::pair<std::string, Eigen::VectorXd>>& effects) {
  Setup setup;
  make_setup(setup, problem, markers, placements, false, {});
  std::vector<std::unique_ptr<Effect>> owned;
  std::vector<const Effect*> chosen;
  Eigen::VectorXd theta = Eigen::VectorXd::Ones(1);
  for (const auto& [name, values] : effects) {
    std::string why;
    owned.push_back(make_effect(name, setup.context, &why));
    if (!owned.back()) throw nurbs::InputError("effect " + name + " does not apply: " + why);
    if (values.size() != owned.back()->num_parameters())
      throw std::invalid_argument("simulate_markers: " + name + " takes " +
                                  std::to_string(owned.back()->num_parameters()) + " parameters");
    chosen.push_back(owned.back().get());
    theta.conservativeResize(theta.size() + values.size());
    theta.tail(values.size()) = values;
  }
  const Model model = build_model(setup, chosen, theta);
  return marker_predictions(setup, model, theta, markers.size());
}

}  // namespace isospring::fitting
