// Displacement-objective calibration: the prepared model (displacement_model.hpp) driven by Ceres
// (grouped fits) or by the dual Levenberg-Marquardt (per-spring fits).
#include "isospring/fitting/displacement_fit.hpp"

#include <ceres/ceres.h>

#include <chrono>
#include <cmath>
#include <ctime>
#include <memory>
#include <stdexcept>

#include "displacement_model.hpp"
#include "dual_levenberg_marquardt.hpp"
#include "fitted_stiffness.hpp"
#include "isospring/analysis/thread_scope.hpp"
#include "isospring/nurbs/error.hpp"
#include "iteration_reporter.hpp"

namespace isospring::fitting {

namespace {

double process_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// Above this many parameters the dual Levenberg-Marquardt replaces Ceres (see solve_dual).
constexpr int kMaxCeresParameters = 64;

// Ceres wrapper of the prepared model (one block of size 1 per group, as before). Ceres calls
// Evaluate from one thread (num_threads = 1), so the model's factorisation cache is safe.
class DisplacementCost : public ceres::CostFunction {
 public:
  explicit DisplacementCost(detail::DisplacementModel& model) : model_(model) {
    set_num_residuals(model.num_residuals());
    for (int g = 0; g < model.num_parameters(); ++g) mutable_parameter_block_sizes()->push_back(1);
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const int groups = model_.num_parameters();
    Eigen::VectorXd theta(groups);
    for (int g = 0; g < groups; ++g) theta[g] = parameters[g][0];
    if (!model_.evaluate(theta, r_, jacobians ? &j_ : nullptr)) return false;
    Eigen::Map<Eigen::VectorXd>(residuals, r_.size()) = r_;
    if (jacobians)
      for (int g = 0; g < groups; ++g)
        if (jacobians[g]) Eigen::Map<Eigen::VectorXd>(jacobians[g], r_.size()) = j_.col(g);
    return true;
  }

 private:
  detail::DisplacementModel& model_;
  mutable Eigen::VectorXd r_;
  mutable Eigen::MatrixXd j_;
};

// sqrt(w) (theta_s - phi_a): pulls a spring's log-stiffness towards its group's shared value
// phi_a (a free parameter).
class EqualityRegularization : public ceres::SizedCostFunction<1, 1, 1> {
 public:
  explicit EqualityRegularization(double weight) : root_weight_(std::sqrt(weight)) {}
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    residuals[0] = root_weight_ * (parameters[0][0] - parameters[1][0]);
    if (jacobians) {
      if (jacobians[0]) jacobians[0][0] = root_weight_;
      if (jacobians[1]) jacobians[1][0] = -root_weight_;
    }
    return true;
  }

 private:
  double root_weight_;
};

// Initial stiffness: k_s = E L0_s (the dimensionally right scale of a lattice spring), then one
// common factor fitted in closed form, since u(alpha k) = u(k) / alpha.
Eigen::VectorXd initial_stiffness(detail::DisplacementModel& model, const Grouping& grouping,
                                  double youngs_modulus) {
  // Volume terms: kappa = E / 4 (the order of the bulk stiffness a lattice of central springs
  // lacks at nu = 1/3: lambda - mu = 3E / 8); the common factor below rescales both kinds.
  Eigen::VectorXd k(grouping.num_groups());
  const std::vector<bool> volume = grouping.volume_groups();
  for (int g = 0; g < grouping.num_groups(); ++g)
    k[g] = volume[static_cast<size_t>(g)] ? 0.25 * youngs_modulus
                                          : youngs_modulus * grouping.centre[g];
  Eigen::VectorXd r;
  if (!model.evaluate(k.array().log().matrix(), r, nullptr))
    throw std::runtime_error("calibration: the spring network is a mechanism under the supports");
  // r = s u - s u_ref: solve min |s u / a - s u_ref|^2 for the factor a.
  const Eigen::VectorXd& sr = model.scaled_reference();
  const Eigen::VectorXd su = r + sr;
  const double uu = su.squaredNorm(), ur = su.dot(sr);
  if (ur > 0.0) k *= uu / ur;
  return k;
}

// Prior of every parameter for the regularisation: the mean initial log-stiffness of its
// regularisation group (with a per-spring start from the grouped optimum, that group's value).
Eigen::VectorXd regularization_prior(const DisplacementFitOptions& options,
                                     const std::vector<double>& theta) {
  const Grouping& reg = options.regularization_groups;
  const auto groups = static_cast<int>(theta.size());
  if (static_cast<int>(reg.group_of_spring.size()) != groups)
    throw nurbs::InputError(
        "calibration: regularization_groups must assign every parameter to a group");
  std::vector<double> sum(static_cast<size_t>(reg.num_groups()), 0.0);
  std::vector<int> members(sum.size(), 0);
  for (int g = 0; g < groups; ++g) {
    const int a = reg.group_of_spring[g];
    if (a < 0 || a >= reg.num_groups())
      throw nurbs::InputError("calibration: a regularization group is out of range");
    sum[a] += theta[g];
    ++members[a];
  }
  Eigen::VectorXd prior(groups);
  for (int g = 0; g < groups; ++g)
    prior[g] = sum[reg.group_of_spring[g]] / members[reg.group_of_spring[g]];
  return prior;
}

// Grouped fits (few parameters): Ceres' LM with dense QR.
void solve_with_ceres(detail::DisplacementModel& model, const DisplacementFitOptions& options,
                      double log_floor, const Eigen::VectorXd& prior, std::vector<double>& theta,
                      DisplacementFitResult& result) {
  const int groups = model.num_parameters();
  ceres::Problem problem;
  std::vector<double*> blocks;
  for (auto& t : theta) blocks.push_back(&t);
  problem.AddResidualBlock(new DisplacementCost(model), nullptr, blocks);
  for (int g = 0; g < groups && !options.upper_bounds.empty(); ++g)
    problem.SetParameterUpperBound(blocks[g], 0, std::log(options.upper_bounds[g]));
  for (int g = 0; g < groups; ++g) problem.SetParameterLowerBound(blocks[g], 0, log_floor);
  // Shared values start at the group means of the start (prior) and are free.
  std::vector<double> shared;
  if (options.regularization > 0.0) {
    const std::vector<int>& group = options.regularization_groups.group_of_spring;
    shared.assign(static_cast<size_t>(options.regularization_groups.num_groups()), 0.0);
    for (int g = 0; g < groups; ++g) shared[group[g]] = prior[g];
    for (int g = 0; g < groups; ++g)
      problem.AddResidualBlock(new EqualityRegularization(options.regularization), nullptr,
                               &theta[g], &shared[group[g]]);
  }

  ceres::Solver::Options solver_options;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.function_tolerance = 1e-12;
  solver_options.gradient_tolerance = 1e-14;
  solver_options.parameter_tolerance = 1e-12;
  solver_options.num_threads = 1;
  solver_options.linear_solver_type = ceres::DENSE_QR;
  detail::IterationReporter reporter(options.on_iteration);
  if (options.on_iteration) solver_options.callbacks.push_back(&reporter);
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  result.iterations = static_cast<int>(summary.iterations.size()) - 1;
  result.cost = summary.final_cost;
  result.converged = summary.termination_type == ceres::CONVERGENCE;
  result.message = summary.message;
}

// Per-spring fits (parameters outnumber residuals): LM with the step from the m x m dual system.
void solve_dual(detail::DisplacementModel& model, const DisplacementFitOptions& options,
                double log_floor, const Eigen::VectorXd& prior, std::vector<double>& theta,
                DisplacementFitResult& result) {
  const int groups = model.num_parameters();
  detail::BoundedLeastSquares problem;
  problem.evaluate = [&model](const Eigen::VectorXd& x, Eigen::VectorXd& r, Eigen::MatrixXd* j) {
    return model.evaluate(x, r, j);
  };
  problem.gram = [&model](const Eigen::VectorXd& weight, Eigen::MatrixXd& gram) {
    return model.gram(weight, gram);
  };
  problem.k_form = [&model](const Eigen::VectorXd& weight, const std::vector<Eigen::Index>& rows,
                            Eigen::MatrixXd& k, Eigen::MatrixXd& k_squared, Eigen::MatrixXd& g) {
    return model.dual_k_form(weight, rows, k, k_squared, g);
  };
  problem.lower = Eigen::VectorXd::Constant(groups, log_floor);
  problem.upper = Eigen::VectorXd::Constant(groups, INFINITY);
  for (int g = 0; g < groups && !options.upper_bounds.empty(); ++g)
    problem.upper[g] = std::log(options.upper_bounds[g]);
  if (options.regularization > 0.0) {
    problem.prior = prior;
    problem.prior_groups = options.regularization_groups.group_of_spring;
    problem.prior_weight = options.regularization;
  }
  detail::DualLmOptions lm;
  lm.max_iterations = options.max_iterations;
  // Gauss-Newton converges only linearly on this non-zero-residual problem once the data terms
  // are fitted: the last 1e-6 of the cost takes as many iterations as the first 99.9999%. A
  // relative change of 1e-10 moves %e_rms by < 1e-10 relative, far below anything measurable.
  lm.function_tolerance = 1e-10;
  lm.on_iteration = options.on_iteration;
  Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(theta.data(), groups);
  // One thread for Eigen's dense products here (restored on return): its only parallel work is
  // the blocked Cholesky of the ~500 x 500 dual system, too small to pay for the threads. Two
  // threads cost ~0.25 s more CPU over a 6^3 per-spring fit (idle-spinning OpenMP workers) and
  // gained no wall time on 2 cores.
  const analysis::ThreadScope single_thread(1);
  const detail::DualLmSummary summary = detail::solve_dual_levenberg_marquardt(problem, x, lm);
  for (int g = 0; g < groups; ++g) theta[g] = x[g];
  result.iterations = summary.iterations;
  result.cost = summary.cost;
  result.converged = summary.converged;
  result.message = summary.message;
}

}  // namespace

std::vector<double> per_element_values(const DisplacementFitResult& fit) {
  std::vector<double> values = fit.spring_stiffness;
  values.insert(values.end(), fit.volume_modulus.begin(), fit.volume_modulus.end());
  return values;
}

int num_displacement_residuals(const DisplacementFitData& data) {
  return static_cast<int>(data.references.size()) * static_cast<int>(data.particle_of_node.size()) *
         data.network.dimension;
}

bool displacement_residuals(const DisplacementFitData& data, const Grouping& grouping,
                            const Eigen::VectorXd& theta, Eigen::VectorXd& residuals,
                            Eigen::MatrixXd* jacobian) {
  detail::DisplacementModel model(data, grouping);
  return model.evaluate(theta, residuals, jacobian);
}

DisplacementFitResult fit_displacements(const DisplacementFitData& data,
                                        const DisplacementFitOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = process_cpu_seconds();
  const Grouping& grouping = options.grouping;
  detail::DisplacementModel model(data, grouping);
  const int groups = grouping.num_groups();
  if (!options.initial.empty() && static_cast<int>(options.initial.size()) != groups)
    throw nurbs::InputError("calibration: the initial stiffnesses do not match the groups");
  if (!options.upper_bounds.empty() && static_cast<int>(options.upper_bounds.size()) != groups)
    throw nurbs::InputError("calibration: the upper bounds do not match the groups");
  Eigen::VectorXd k0 = options.initial.empty()
                           ? initial_stiffness(model, grouping, options.youngs_modulus)
                           : Eigen::Map<const Eigen::VectorXd>(options.initial.data(), groups);
  // The floor never lies above a starting value: a start taken from an earlier fit (per-spring
  // fits start at the grouped optimum, whose spread can exceed 1 / min_stiffness_ratio) must not
  // be moved, or the fit would start, and end, worse than the fit it refines.
  if (!(k0.minCoeff() > 0.0) || !k0.allFinite())
    throw nurbs::InputError("calibration: initial stiffnesses must be positive and finite");
  const double log_floor =
      std::log(std::min(options.min_stiffness_ratio * k0.maxCoeff(), k0.minCoeff()));
  std::vector<double> theta(static_cast<size_t>(groups));
  for (int g = 0; g < groups; ++g) {
    double k = k0[g];
    if (!options.upper_bounds.empty()) k = std::min(k, 0.5 * options.upper_bounds[g]);
    theta[g] = std::max(std::log(k), log_floor);
  }
  const Eigen::VectorXd prior =
      options.regularization > 0.0 ? regularization_prior(options, theta) : Eigen::VectorXd();

  DisplacementFitResult result;
  // Ceres' dense QR is the right tool for a handful of groups; beyond that the dense Jacobian
  // makes its P x P normal equations the cost (and singular when P > residuals).
  if (groups > kMaxCeresParameters)
    solve_dual(model, options, log_floor, prior, theta, result);
  else
    solve_with_ceres(model, options, log_floor, prior, theta, result);

  detail::set_fitted_stiffnesses(theta, log_floor, grouping, result);
  Eigen::VectorXd r;
  Eigen::VectorXd final_theta = Eigen::Map<Eigen::VectorXd>(theta.data(), groups);
  if (!model.evaluate(final_theta, r, nullptr))
    throw std::runtime_error("calibration: the fitted spring network is a mechanism");
  const int rows = static_cast<int>(data.particle_of_node.size()) * data.network.dimension;
  for (size_t c = 0; c < data.references.size(); ++c)
    result.percent_e_rms.push_back(100.0 *
                                   r.segment(static_cast<Eigen::Index>(c) * rows, rows).norm());
  result.percent_e_max = model.percent_e_max(r);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.cpu_seconds = process_cpu_seconds() - cpu_start;
  return result;
}

}  // namespace isospring::fitting
