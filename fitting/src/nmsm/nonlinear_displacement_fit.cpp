// The displacement objective with the spring network's nonlinear equilibrium as its response
// (nonlinear_displacement_fit.hpp), driven by Ceres' Levenberg-Marquardt.
#include "isospring/fitting/nonlinear_displacement_fit.hpp"

#include <ceres/ceres.h>

#include <Eigen/SparseCholesky>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "fitted_stiffness.hpp"
#include "isospring/analysis/spring_mechanics.hpp"
#include "isospring/analysis/spring_static.hpp"
#include "isospring/nurbs/error.hpp"
#include "iteration_reporter.hpp"

namespace isospring::fitting {

namespace {

using analysis::FreeDofSet;
using analysis::SpringNetwork;
using Ldlt = Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>;

constexpr int kMaxGroups = 64;
// Newton stops at this relative residual (or when it no longer decreases) and succeeds at
// kAccept: the fit's finite-difference-free Jacobian assumes an equilibrium, and 1e-10 of the
// load is far below the 1e-4 of a displacement that %e_rms resolves.
constexpr double kTarget = 1e-13, kAccept = 1e-10;

Eigen::VectorXd free_residual(const SpringNetwork& network, const FreeDofSet& dofs,
                              const Eigen::VectorXd& x0, const Eigen::VectorXd& force,
                              const Eigen::VectorXd& u) {
  return dofs.restrict(Eigen::VectorXd(force + analysis::spring_forces(network, x0 + u)));
}

// The potential Pi(u) = E(x0 + u) - f . u whose stationary points are the equilibria.
double potential(const SpringNetwork& network, const Eigen::VectorXd& x0,
                 const Eigen::VectorXd& force, const Eigen::VectorXd& u) {
  return analysis::spring_energy(network, x0 + u) - force.dot(u);
}

// Factorises the free tangent, shifted by tau I (growing from 1e-8 of its largest diagonal entry)
// until the factor has positive pivots; false when no shift does. `shifted` says whether one
// was needed. An indefinite tangent (past a limit point, cells in compression) gives a Newton
// step towards a saddle or a maximum of Pi, which is where Newton on |r| alone used to stall.
bool factor_positive(const Eigen::SparseMatrix<double>& tangent, Ldlt& solver, bool& shifted) {
  shifted = false;
  solver.compute(tangent);
  if (solver.info() == Eigen::Success && solver.vectorD().minCoeff() > 0.0) return true;
  const double diagonal = tangent.diagonal().cwiseAbs().maxCoeff();
  Eigen::SparseMatrix<double> identity(tangent.rows(), tangent.cols());
  identity.setIdentity();
  shifted = true;
  for (double tau = 1e-8 * diagonal; tau < 1e8 * diagonal; tau *= 4.0) {
    solver.compute(tangent + tau * identity);
    if (solver.info() == Eigen::Success && solver.vectorD().minCoeff() > 0.0) return true;
  }
  return false;
}

// Newton from u (updated in place) minimising Pi on the free DOFs; true when |r| <= kAccept |f|.
// A step is accepted on an Armijo decrease of Pi or, with an unshifted (positive definite)
// tangent, on a decrease of |r|: near the solution Pi's changes drown in round-off while |r|
// still converges quadratically. So it finds a stable equilibrium (a local minimum of Pi),
// which exists whenever the terms' energy grows faster than linearly in every free direction
// (springs and cell terms do), where Newton on |r| stopped at a singular tangent.
bool newton(const SpringNetwork& network, const FreeDofSet& dofs, const Eigen::VectorXd& x0,
            const Eigen::VectorXd& force, Eigen::VectorXd& u) {
  const double scale = std::max(dofs.restrict(force).norm(), 1e-300);
  Eigen::VectorXd r = free_residual(network, dofs, x0, force, u);
  double pi = potential(network, x0, force, u);
  Ldlt solver;
  for (int it = 0; it < 100 && r.norm() > kTarget * scale; ++it) {
    bool shifted = false;
    if (!factor_positive(dofs.restrict(analysis::tangent_stiffness(network, x0 + u)), solver,
                         shifted))
      break;
    const Eigen::VectorXd step = solver.solve(r);  // -grad Pi = r on the free DOFs
    const Eigen::VectorXd delta = dofs.expand(step);
    if (!delta.allFinite()) break;
    const double slope = -r.dot(step);  // d Pi / dt at t = 0, negative
    bool accepted = false;
    for (double t = 1.0; t > 1e-6 && !accepted; t *= 0.5) {
      const Eigen::VectorXd trial_u = u + t * delta;
      const double trial_pi = potential(network, x0, force, trial_u);
      const Eigen::VectorXd trial_r = free_residual(network, dofs, x0, force, trial_u);
      if (!std::isfinite(trial_pi) || !trial_r.allFinite()) continue;
      if (trial_pi <= pi + 1e-4 * t * slope || (!shifted && trial_r.norm() < r.norm())) {
        u = trial_u;
        r = trial_r;
        pi = trial_pi;
        accepted = true;
      }
    }
    if (!accepted) break;  // no progress: round-off
  }
  return r.norm() <= kAccept * scale && u.allFinite();
}

// From rest: the whole load, then 4, 16 and 64 equal steps when Newton fails.
bool solve_from_rest(const SpringNetwork& network, const FreeDofSet& dofs,
                     const Eigen::VectorXd& x0, const Eigen::VectorXd& force, Eigen::VectorXd& u) {
  for (int steps : {1, 4, 16, 64}) {
    u = Eigen::VectorXd::Zero(force.size());
    bool ok = true;
    for (int s = 1; s <= steps && ok; ++s)
      ok = newton(network, dofs, x0, force * (static_cast<double>(s) / steps), u);
    if (ok) return true;
  }
  return false;
}

void check_options(const DisplacementFitOptions& options) {
  if (options.grouping.num_groups() > kMaxGroups)
    throw nurbs::InputError("calibration: the large-deformation fit takes at most " +
                            std::to_string(kMaxGroups) + " stiffness groups, got " +
                            std::to_string(options.grouping.num_groups()) +
                            "; use a larger gamma (per-spring freedom is fitted linearly only)");
  if (options.regularization > 0.0)
    throw nurbs::InputError(
        "calibration: the large-deformation fit has no regularisation; it fits grouped "
        "stiffnesses only");
}

// The prepared nonlinear objective: the network with one sub-network per group (its forces are
// the group's f_g), free DOFs, residual scales and every case's last equilibrium.
class NonlinearModel {
 public:
  NonlinearModel(const DisplacementFitData& data, const Grouping& grouping)
      : data_(data),
        grouping_(grouping),
        dim_(data.network.dimension),
        rows_(static_cast<int>(data.particle_of_node.size()) * data.network.dimension),
        dofs_(static_cast<int>(data.network.positions.size()) * data.network.dimension,
              analysis::constrained_dofs(data.network, data.constrained_dofs)),
        network_(data.network),
        x0_(analysis::flat_positions(data.network)) {
    if (data.loads.empty() || data.loads.size() != data.references.size())
      throw nurbs::InputError("calibration: give at least one load case with a reference");
    if (grouping.group_of_spring.size() != data.network.springs.size() ||
        grouping.group_of_volume.size() != data.network.volumes.size())
      throw nurbs::InputError("calibration: the stiffness grouping does not cover every term");
    group_networks_.resize(static_cast<size_t>(grouping.num_groups()));
    for (auto& g : group_networks_) {
      g.positions = data.network.positions;
      g.dimension = dim_;
      g.fixed = data.network.fixed;
    }
    for (size_t s = 0; s < data.network.springs.size(); ++s)
      group_networks_[grouping.group_of_spring[s]].springs.push_back(data.network.springs[s]);
    for (size_t v = 0; v < data.network.volumes.size(); ++v)
      group_networks_[grouping.group_of_volume[v]].volumes.push_back(data.network.volumes[v]);
    const int nodes = static_cast<int>(data.particle_of_node.size());
    for (size_t c = 0; c < data.loads.size(); ++c) {
      if (data.loads[c].size() != x0_.size() || data.references[c].size() != rows_)
        throw nurbs::InputError("calibration: load case " + std::to_string(c) +
                                " has loads or reference displacements of the wrong size");
      double o_max = 0.0;
      for (int a = 0; a < nodes; ++a)
        o_max = std::max(o_max, data.references[c].segment(a * dim_, dim_).norm());
      if (!(o_max > 0.0) || !data.references[c].allFinite())
        throw nurbs::InputError("calibration: load case " + std::to_string(c) +
                                " has a zero or non-finite reference displacement");
      scale_.push_back(1.0 / (o_max * std::sqrt(static_cast<double>(nodes))));
    }
  }

  int num_residuals() const { return static_cast<int>(data_.loads.size()) * rows_; }
  int num_parameters() const { return grouping_.num_groups(); }

  // Residuals (and Jacobian) at theta. Each case's equilibrium is found by Newton from the
  // equilibrium of the best point evaluated so far (lowest cost), else from rest: a warm start
  // from the LAST evaluation made the objective depend on the optimiser's history, since a
  // rejected trial step can leave a case on another branch of equilibria, and the next trial
  // next to the current point then continued that branch (measured: a trust region shrinking
  // onto a point of cost 4.7 whose neighbours evaluated at 31).
  bool evaluate(const Eigen::VectorXd& theta, Eigen::VectorXd& residuals,
                Eigen::MatrixXd* jacobian) {
    if (!theta.allFinite() || !set_stiffness(theta)) return false;
    residuals.resize(num_residuals());
    if (jacobian) jacobian->setZero(num_residuals(), num_parameters());
    std::vector<Eigen::VectorXd> equilibria(data_.loads.size());
    for (size_t c = 0; c < data_.loads.size(); ++c) {
      Eigen::VectorXd u = best_.empty() ? Eigen::VectorXd() : best_[c];
      if (!(u.size() && newton(network_, dofs_, x0_, data_.loads[c], u)) &&
          !solve_from_rest(network_, dofs_, x0_, data_.loads[c], u))
        return false;
      const auto row0 = static_cast<Eigen::Index>(c) * rows_;
      for (int a = 0; a < rows_ / dim_; ++a)
        residuals.segment(row0 + a * dim_, dim_) =
            scale_[c] * (u.segment(data_.particle_of_node[a] * dim_, dim_) -
                         data_.references[c].segment(a * dim_, dim_));
      if (jacobian && !add_jacobian(c, u, *jacobian)) return false;
      equilibria[c] = std::move(u);
    }
    if (!residuals.allFinite()) return false;
    const double cost = residuals.squaredNorm();
    if (best_.empty() || cost < best_cost_) {
      best_cost_ = cost;
      best_theta_ = theta;
      best_ = std::move(equilibria);
    }
    return true;
  }

  /// The lowest-cost point evaluated so far and its cost (sum of squared residuals).
  const Eigen::VectorXd& best_theta() const { return best_theta_; }
  double best_cost() const { return best_cost_; }

 private:
  bool set_stiffness(const Eigen::VectorXd& theta) {
    const Eigen::VectorXd k = theta.array().exp();
    if (!k.allFinite() || !(k.minCoeff() > 0.0)) return false;
    for (size_t s = 0; s < network_.springs.size(); ++s)
      network_.springs[s].stiffness = k[grouping_.group_of_spring[s]];
    for (size_t v = 0; v < network_.volumes.size(); ++v)
      network_.volumes[v].modulus = k[grouping_.group_of_volume[v]];
    for (int g = 0; g < num_parameters(); ++g) {
      for (auto& s : group_networks_[g].springs) s.stiffness = k[g];
      for (auto& v : group_networks_[g].volumes) v.modulus = k[g];
    }
    return true;
  }

  // du/dtheta_g = K_T^-1 f_g at the equilibrium u of case c, into that case's rows.
  bool add_jacobian(size_t c, const Eigen::VectorXd& u, Eigen::MatrixXd& jacobian) const {
    const Eigen::VectorXd x = x0_ + u;
    Ldlt solver(dofs_.restrict(analysis::tangent_stiffness(network_, x)));
    if (solver.info() != Eigen::Success) return false;
    const auto row0 = static_cast<Eigen::Index>(c) * rows_;
    for (int g = 0; g < num_parameters(); ++g) {
      const Eigen::VectorXd du = dofs_.expand(
          solver.solve(dofs_.restrict(analysis::spring_forces(group_networks_[g], x))));
      if (!du.allFinite()) return false;
      for (int a = 0; a < rows_ / dim_; ++a)
        jacobian.col(g).segment(row0 + a * dim_, dim_) =
            scale_[c] * du.segment(data_.particle_of_node[a] * dim_, dim_);
    }
    return true;
  }

  const DisplacementFitData& data_;
  const Grouping& grouping_;
  int dim_, rows_;
  FreeDofSet dofs_;
  SpringNetwork network_;
  std::vector<SpringNetwork> group_networks_;
  Eigen::VectorXd x0_;
  std::vector<double> scale_;
  std::vector<Eigen::VectorXd> best_;  // per case: the best point's equilibrium (warm start)
  Eigen::VectorXd best_theta_;
  double best_cost_ = 0.0;
};

class NonlinearCost : public ceres::CostFunction {
 public:
  explicit NonlinearCost(NonlinearModel& model) : model_(model) {
    set_num_residuals(model.num_residuals());
    for (int g = 0; g < model.num_parameters(); ++g) mutable_parameter_block_sizes()->push_back(1);
  }
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    Eigen::VectorXd theta(model_.num_parameters());
    for (int g = 0; g < theta.size(); ++g) theta[g] = parameters[g][0];
    if (!model_.evaluate(theta, r_, jacobians ? &j_ : nullptr)) return false;
    Eigen::Map<Eigen::VectorXd>(residuals, r_.size()) = r_;
    if (jacobians)
      for (int g = 0; g < theta.size(); ++g)
        if (jacobians[g]) Eigen::Map<Eigen::VectorXd>(jacobians[g], r_.size()) = j_.col(g);
    return true;
  }

 private:
  NonlinearModel& model_;
  mutable Eigen::VectorXd r_;
  mutable Eigen::MatrixXd j_;
};

}  // namespace

bool spring_equilibrium(const analysis::SpringNetwork& network, const Eigen::VectorXd& force,
                        const std::vector<int>& extra_constrained, Eigen::VectorXd& u,
                        const Eigen::VectorXd& start) {
  const FreeDofSet dofs(static_cast<int>(force.size()),
                        analysis::constrained_dofs(network, extra_constrained));
  const Eigen::VectorXd x0 = analysis::flat_positions(network);
  if (start.size() == force.size()) {
    u = start;
    if (newton(network, dofs, x0, force, u)) return true;
  }
  return solve_from_rest(network, dofs, x0, force, u);
}

bool nonlinear_displacement_residuals(const DisplacementFitData& data, const Grouping& grouping,
                                      const Eigen::VectorXd& theta, Eigen::VectorXd& residuals,
                                      Eigen::MatrixXd* jacobian) {
  NonlinearModel model(data, grouping);
  return model.evaluate(theta, residuals, jacobian);
}

DisplacementFitResult fit_displacements_nonlinear(const DisplacementFitData& data,
                                                  const DisplacementFitOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  check_options(options);
  const Grouping& grouping = options.grouping;
  const int groups = grouping.num_groups();
  std::vector<double> k0 = options.initial;
  if (k0.empty()) k0 = fit_displacements(data, options).group_stiffness;
  if (static_cast<int>(k0.size()) != groups)
    throw nurbs::InputError("calibration: the initial stiffnesses do not match the groups");
  const double k_max = *std::max_element(k0.begin(), k0.end());
  const double k_min = *std::min_element(k0.begin(), k0.end());
  if (!(k_min > 0.0) || !std::isfinite(k_max))
    throw nurbs::InputError("calibration: initial stiffnesses must be positive and finite");
  // The linear fit's floor (displacement_fit.hpp): never above a starting value.
  const double log_floor = std::log(std::min(options.min_stiffness_ratio * k_max, k_min));

  NonlinearModel model(data, grouping);
  std::vector<double> theta;
  for (double k : k0) theta.push_back(std::log(k));
  const std::vector<double> log_k0 = theta;
  ceres::Problem problem;
  std::vector<double*> blocks;
  for (auto& t : theta) blocks.push_back(&t);
  problem.AddResidualBlock(new NonlinearCost(model), nullptr, blocks);
  for (double* b : blocks) problem.SetParameterLowerBound(b, 0, log_floor);
  ceres::Solver::Options solver_options;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.function_tolerance = 1e-12;
  solver_options.gradient_tolerance = 1e-14;
  solver_options.parameter_tolerance = 1e-12;
  solver_options.num_threads = 1;  // the model's warm starts are not thread-safe
  solver_options.linear_solver_type = ceres::DENSE_QR;
  detail::IterationReporter reporter(options.on_iteration);
  if (options.on_iteration) solver_options.callbacks.push_back(&reporter);
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);

  DisplacementFitResult result;
  result.iterations = static_cast<int>(summary.iterations.size()) - 1;
  result.converged = summary.termination_type == ceres::CONVERGENCE;
  result.message = summary.message;
  // The model is judged (and used) by its equilibria from rest; the optimiser's by equilibria
  // continued from its best point, which can lie on another branch. Keep the fit's best point
  // unless, from rest, it explains the cases worse than the start (or not at all).
  Eigen::VectorXd best = model.best_theta().size()
                             ? model.best_theta()
                             : Eigen::VectorXd(Eigen::Map<Eigen::VectorXd>(theta.data(), groups));
  const Eigen::VectorXd initial = Eigen::Map<const Eigen::VectorXd>(log_k0.data(), groups);
  Eigen::VectorXd r, r_initial;
  const bool at_best = nonlinear_displacement_residuals(data, grouping, best, r, nullptr);
  const bool at_initial =
      nonlinear_displacement_residuals(data, grouping, initial, r_initial, nullptr);
  if (at_initial && (!at_best || r_initial.squaredNorm() < r.squaredNorm())) {
    best = initial;
    r = r_initial;
    result.message += "; kept the initial stiffnesses: from rest they explain the cases better";
  } else if (!at_best) {
    throw std::runtime_error(
        "calibration: the fitted spring network has no equilibrium under a fitted load");
  }
  theta.assign(best.data(), best.data() + groups);
  result.cost = 0.5 * r.squaredNorm();
  detail::set_fitted_stiffnesses(theta, log_floor, grouping, result);
  const int rows = static_cast<int>(data.particle_of_node.size()) * data.network.dimension;
  const int dim = data.network.dimension;
  for (size_t c = 0; c < data.references.size(); ++c) {
    const auto block = r.segment(static_cast<Eigen::Index>(c) * rows, rows);
    result.percent_e_rms.push_back(100.0 * block.norm());
    double worst = 0.0;
    for (int a = 0; a < rows / dim; ++a)
      worst = std::max(worst, block.segment(a * dim, dim).norm());
    result.percent_e_max.push_back(100.0 * worst *
                                   std::sqrt(static_cast<double>(data.particle_of_node.size())));
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace isospring::fitting
