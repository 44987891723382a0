// The measured-data loop's model and fits: the fixed setup, the forward model of a set of
// effects, the weighted least-squares fit and the residuals at the markers (loop_state.hpp).
#include <ceres/ceres.h>

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <optional>

#include "identify/fit_stopping.hpp"
#include "identify/loop_state.hpp"
#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/validation.hpp"
#include "isospring/nurbs/error.hpp"
#include "quiet_solver_warnings.hpp"

namespace isospring::fitting::identify_loop {

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

class DataCost : public ceres::CostFunction {
 public:
  DataCost(const ForwardModel& model, const std::vector<Eigen::VectorXd>& measured,
           const std::vector<Eigen::VectorXd>& weights, FitProgress& progress)
      : model_(model), measured_(measured), weights_(weights), progress_(progress) {
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
    if (with_jacobian) {
      // The residual is measured minus predicted, so the step's Jacobian is -J_ceres.
      using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
      progress_.predicted_reduction =
          gauss_newton_reduction(-Eigen::Map<const RowMajor>(jacobians[0], num_residuals(), p),
                                 Eigen::Map<const Eigen::VectorXd>(residuals, num_residuals()));
    }
    return true;
  }

 private:
  const ForwardModel& model_;
  const std::vector<Eigen::VectorXd>& measured_;
  const std::vector<Eigen::VectorXd>& weights_;
  FitProgress& progress_;
};

Eigen::Index setup_rows(const std::vector<Eigen::VectorXd>& weights) {
  Eigen::Index rows = 0;
  for (const auto& w : weights) rows += w.size();
  return rows;
}

}  // namespace

double gauss_newton_reduction(const Eigen::MatrixXd& jacobian, const Eigen::VectorXd& residual) {
  Eigen::MatrixXd scaled = jacobian;
  for (Eigen::Index j = 0; j < scaled.cols(); ++j) {
    const double norm = scaled.col(j).norm();
    if (norm > 0.0) scaled.col(j) /= norm;
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(scaled);
  const Eigen::VectorXd qtr = qr.householderQ().adjoint() * residual;
  return qtr.head(qr.rank()).squaredNorm();
}

// `cache`: the factorisation cache the model solves with; null: the loop's (setup.factorizations).
Model build_model(const Setup& setup, const std::vector<const Effect*>& effects,
                  const Eigen::VectorXd& warm_start, std::shared_ptr<FactorizationCache> cache) {
  ModelTerms terms;
  terms.num_parameters = setup.material_parameters;
  for (const Effect* effect : effects) terms.num_parameters += effect->num_parameters();
  if (setup.scaled_stiffness.size() > 0) {
    terms.stiffness.push_back({setup.scaled_stiffness, linear_coefficient(0)});
  } else {
    terms.stiffness.push_back({setup.lame.lambda_part, setup.context.lambda});
    terms.stiffness.push_back({setup.lame.mu_part, setup.context.mu});
  }
  for (size_t l = 0; l < setup.nominal_loads.size(); ++l)
    terms.loads.push_back({static_cast<int>(l), setup.nominal_loads[l], constant_coefficient(1.0)});
  Model model;
  model.initial.resize(terms.num_parameters);
  model.initial[0] = 1.0;
  model.lower =
      Eigen::VectorXd::Constant(terms.num_parameters, -std::numeric_limits<double>::infinity());
  model.upper =
      Eigen::VectorXd::Constant(terms.num_parameters, std::numeric_limits<double>::infinity());
  if (setup.material_parameters > 1) model.initial[1] = setup.problem->material.poisson_ratio;
  int first = setup.material_parameters;
  for (const Effect* effect : effects) {
    effect->add_terms(setup.context, first, terms);
    model.initial.segment(first, effect->num_parameters()) = effect->initial_values();
    model.lower.segment(first, effect->num_parameters()) = effect->lower_bounds();
    model.upper.segment(first, effect->num_parameters()) = effect->upper_bounds();
    model.blocks.emplace_back(first, effect->num_parameters());
    first += effect->num_parameters();
  }
  // Warm start: the parameters already fitted keep their values (effects are appended).
  const Eigen::Index keep = std::min(warm_start.size(), model.initial.size());
  model.initial.head(keep) = warm_start.head(keep);
  model.forward = std::make_unique<ForwardModel>(
      std::move(terms), setup.observations, setup.constraints.dofs, setup.constraints.values,
      setup.num_dofs, static_cast<int>(setup.observations.size()),
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

Fit run_fit(const Setup& setup, const Model& model, const std::vector<Eigen::VectorXd>& weights,
            Eigen::MatrixXd* covariance, FitStart start) {
  const QuietSolverWarnings quiet;
  Fit fit;
  fit.theta = model.initial;
  ceres::Problem::Options problem_options;
  problem_options.cost_function_ownership = ceres::TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  FitProgress progress;
  problem.AddResidualBlock(new DataCost(*model.forward, setup.measured, weights, progress), nullptr,
                           fit.theta.data());
  problem.SetParameterLowerBound(fit.theta.data(), 0, 1e-3);
  if (setup.material_parameters > 1) {
    problem.SetParameterLowerBound(fit.theta.data(), 1, -0.9);
    problem.SetParameterUpperBound(fit.theta.data(), 1, 0.49);
  }
  for (Eigen::Index i = setup.material_parameters; i < model.lower.size(); ++i) {
    if (std::isfinite(model.lower[i]))
      problem.SetParameterLowerBound(fit.theta.data(), i, model.lower[i]);
    if (std::isfinite(model.upper[i]))
      problem.SetParameterUpperBound(fit.theta.data(), i, model.upper[i]);
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
  // Ceres' tolerances are relative to the cost; the rule that usually ends a fit is on the RSS
  // decrease in units of the residual variance (fit_stopping.hpp).
  int weighted_rows = 0;
  for (const auto& w : weights) weighted_rows += static_cast<int>((w.array() > 0.0).count());
  NegligibleDecreaseStop stop(setup.negligible_rss,
                              weighted_rows - static_cast<int>(fit.theta.size()), progress);
  options.callbacks.push_back(&stop);
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
  // A new parameter that starts on its bound (support_compliance's log(k_a / k_n) = 0, the
  // one-stiffness support) makes the effect's nested special case: that is fitted first, those
  // parameters held, then all of them from its optimum. Started together, a wide first step
  // pinned log(k_a / k_n) on its upper bound, where the projected steps crawled (the synthetic
  // confined clamp's round-1 fit: 100 iterations, not converged, RSS 0.9 of the nominal one).
  std::vector<int> held;
  for (Eigen::Index i = setup.material_parameters; i < fit.theta.size(); ++i)
    if (start == FitStart::kNewParameters && fit.theta[i] == model.lower[i])
      held.push_back(static_cast<int>(i));
  if (!held.empty()) {
    problem.SetManifold(fit.theta.data(),
                        new ceres::SubsetManifold(static_cast<int>(fit.theta.size()), held));
    ceres::Solve(options, &problem, &summary);
    problem.SetManifold(fit.theta.data(), nullptr);
  }
  progress.stopped = false;
  ceres::Solve(options, &problem, &summary);
  fit.ok = summary.IsSolutionUsable() && std::isfinite(summary.final_cost);
  fit.message = progress.stopped ? "the RSS decrease and its Gauss-Newton prediction fell below " +
                                       std::to_string(setup.negligible_rss) + " residual variances"
                                 : summary.message;
  fit.stopped_negligible = progress.stopped;
  fit.iterations = static_cast<int>(summary.iterations.size()) - 1;
  fit.rss = 2.0 * summary.final_cost;
  fit.rows = weighted_rows;
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

std::vector<Eigen::Vector3d> marker_misfit(const Setup& setup, const Model& model,
                                           const Eigen::VectorXd& theta,
                                           const std::vector<Marker>& markers) {
  const auto predicted = marker_predictions(setup, model, theta, markers.size());
  std::vector<Eigen::Vector3d> residual(markers.size());
  for (size_t m = 0; m < markers.size(); ++m) residual[m] = markers[m].displacement - predicted[m];
  return residual;
}

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
  setup.num_dofs = setup.dofs.num_dofs();
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

}  // namespace isospring::fitting::identify_loop
