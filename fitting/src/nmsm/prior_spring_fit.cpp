// Per-spring fit to many load cases by L-BFGS with an adjoint gradient (header: objective, why).
#include "isospring/fitting/prior_spring_fit.hpp"

#include <ceres/gradient_problem.h>
#include <ceres/gradient_problem_solver.h>
#include <glog/logging.h>

#include <Eigen/CholmodSupport>
#include <Eigen/Sparse>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "isospring/analysis/spring_static.hpp"
#include "isospring/analysis/spring_volume.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::fitting {

namespace {

// K(k) on the free DOFs with a fixed pattern (every element's blocks always present), so
// CHOLMOD's symbolic analysis is done once. Elements are rank one, K_e = k_e g_e g_e^T: springs
// (g = +-n on the two particles) and volume terms (g = dV/dx / sqrt(|V0|)).
class PriorObjective final : public ceres::FirstOrderFunction {
 public:
  PriorObjective(const DisplacementFitData& data, const std::vector<double>& prior, double weight)
      : data_(data),
        dim_(data.network.dimension),
        free_(static_cast<int>(data.network.positions.size()) * data.network.dimension,
              analysis::constrained_dofs(data.network, data.constrained_dofs)),
        weight_(weight) {
    for (double k : prior) log_prior_.push_back(std::log(k));
    const auto& net = data.network;
    begin_.push_back(0);
    auto add = [&](const std::vector<int>& dofs, const Eigen::VectorXd& g) {
      for (size_t a = 0; a < dofs.size(); ++a) {
        dof_.push_back(dofs[a]);
        value_.push_back(g[static_cast<Eigen::Index>(a)]);
      }
      begin_.push_back(static_cast<int>(dof_.size()));
      parameter_.push_back(parameters_);
    };
    for (const auto& s : net.springs) {
      Eigen::Vector3d n =
          net.positions[static_cast<size_t>(s.j)] - net.positions[static_cast<size_t>(s.i)];
      if (dim_ == 2) n.z() = 0.0;
      n.normalize();
      direction_.push_back(n);
      std::vector<int> dofs;
      Eigen::VectorXd g(2 * dim_);
      for (int d = 0; d < dim_; ++d) {
        dofs.push_back(s.i * dim_ + d);
        g[d] = -n[d];
      }
      for (int d = 0; d < dim_; ++d) {
        dofs.push_back(s.j * dim_ + d);
        g[dim_ + d] = n[d];
      }
      add(dofs, g);
      ++parameters_;
    }
    // A cell term's columns (one for a volume term, one per deviatoric mode for a shear term)
    // share its parameter.
    for (const auto& term : net.volumes) {
      for (const Eigen::VectorXd& column : analysis::rest_stiffness_columns(net, term))
        add(analysis::volume_dofs(term, dim_), column);
      ++parameters_;
    }
    const int nodes = static_cast<int>(data.particle_of_node.size());
    for (const auto& ref : data.references) {
      double o_max = 0.0;
      for (int a = 0; a < nodes; ++a) o_max = std::max(o_max, ref.segment(a * dim_, dim_).norm());
      if (!(o_max > 0.0))
        throw nurbs::InputError("prior spring fit: a load case has zero reference displacement");
      scale_.push_back(1.0 / (o_max * std::sqrt(static_cast<double>(nodes))));
      load_.push_back(free_.restrict(Eigen::VectorXd(data.loads[scale_.size() - 1])));
    }
    pattern_ = assemble(std::vector<double>(static_cast<size_t>(NumParameters()), 1.0));
    solver_.cholmod().print = 0;
    solver_.analyzePattern(pattern_);
  }

  int NumParameters() const override { return parameters_; }

  bool Evaluate(const double* theta, double* cost, double* gradient) const override {
    const auto springs = static_cast<size_t>(NumParameters());
    std::vector<double> k(springs);
    for (size_t s = 0; s < springs; ++s) {
      k[s] = std::exp(theta[s]);
      if (!std::isfinite(k[s]) || !(k[s] > 0.0)) return false;
    }
    const Eigen::SparseMatrix<double> K = assemble(k);
    solver_.factorize(K);
    if (solver_.info() != Eigen::Success) return false;
    const double cases = static_cast<double>(load_.size());
    double data_term = 0.0;
    if (gradient) std::fill(gradient, gradient + springs, 0.0);
    errors_.assign(load_.size(), 0.0);
    for (size_t c = 0; c < load_.size(); ++c) {
      const Eigen::VectorXd u_free = solver_.solve(load_[c]);
      if (!u_free.allFinite()) return false;
      const Eigen::VectorXd u = free_.expand(u_free);
      // r = s (P u - u_ref); adjoint right-hand side P^T s r on the particles.
      Eigen::VectorXd adjoint = Eigen::VectorXd::Zero(u.size());
      double sum = 0.0;
      for (size_t a = 0; a < data_.particle_of_node.size(); ++a) {
        const Eigen::Index node = static_cast<Eigen::Index>(a) * dim_;
        const Eigen::Index particle = static_cast<Eigen::Index>(data_.particle_of_node[a]) * dim_;
        const Eigen::VectorXd r =
            scale_[c] * (u.segment(particle, dim_) - data_.references[c].segment(node, dim_));
        sum += r.squaredNorm();
        adjoint.segment(particle, dim_) += scale_[c] * r;
      }
      errors_[c] = std::sqrt(sum);
      data_term += 0.5 * sum / cases;
      if (!gradient) continue;
      const Eigen::VectorXd lambda = free_.expand(solver_.solve(free_.restrict(adjoint)));
      for (size_t s = 0; s + 1 < begin_.size(); ++s) {
        double gu = 0.0, gl = 0.0;
        if (s < direction_.size()) {  // a spring: g^T v = n . (v_j - v_i)
          const auto& spring = data_.network.springs[s];
          const Eigen::Index i = static_cast<Eigen::Index>(spring.i) * dim_;
          const Eigen::Index j = static_cast<Eigen::Index>(spring.j) * dim_;
          const Eigen::VectorXd n = direction_[s].head(dim_);
          gu = n.dot(u.segment(j, dim_) - u.segment(i, dim_));
          gl = n.dot(lambda.segment(j, dim_) - lambda.segment(i, dim_));
        } else {  // a cell term's column: g^T v over its corners
          for (int a = begin_[s]; a < begin_[s + 1]; ++a) {
            gu += value_[a] * u[dof_[a]];
            gl += value_[a] * lambda[dof_[a]];
          }
        }
        const int p = parameter_[s];
        gradient[p] -= k[p] * gl * gu / cases;  // d/dtheta = k d/dk
      }
    }
    double penalty = 0.0;
    const double w = weight_ / static_cast<double>(springs);
    for (size_t s = 0; s < springs; ++s) {
      const double d = theta[s] - log_prior_[s];
      penalty += 0.5 * w * d * d;
      if (gradient) gradient[s] += w * d;
    }
    *cost = data_term + penalty;
    return std::isfinite(*cost);
  }

  // Per case 100 |r_c| = %e_rms,c at the last evaluation.
  const std::vector<double>& last_errors() const { return errors_; }

 private:
  Eigen::SparseMatrix<double> assemble(const std::vector<double>& k) const {
    std::vector<Eigen::Triplet<double>> entries;
    for (size_t s = 0; s + 1 < begin_.size(); ++s)
      for (int a = begin_[s]; a < begin_[s + 1]; ++a) {
        const int row = free_.free_index(dof_[a]);
        if (row < 0) continue;
        for (int b = begin_[s]; b < begin_[s + 1]; ++b) {
          const int col = free_.free_index(dof_[b]);
          if (col >= 0) entries.emplace_back(row, col, k[parameter_[s]] * value_[a] * value_[b]);
        }
      }
    Eigen::SparseMatrix<double> K(free_.num_free(), free_.num_free());
    K.setFromTriplets(entries.begin(), entries.end());
    return K;
  }

  const DisplacementFitData& data_;
  int dim_;
  analysis::FreeDofSet free_;
  double weight_;
  std::vector<double> log_prior_, scale_;
  std::vector<Eigen::Vector3d> direction_;  // per spring: unit (x_j - x_i)
  std::vector<int> begin_, dof_;  // column s: entries [begin_[s], begin_[s + 1]) of dof_, value_
  std::vector<int> parameter_;    // column -> parameter (springs, then cell terms)
  int parameters_ = 0;
  std::vector<double> value_;
  std::vector<Eigen::VectorXd> load_;
  Eigen::SparseMatrix<double> pattern_;
  mutable Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> solver_;
  mutable std::vector<double> errors_;
};

}  // namespace

PriorSpringFitResult fit_springs_with_prior(const DisplacementFitData& data,
                                            const PriorSpringFitOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  if (options.prior.size() != data.network.springs.size() + data.network.volumes.size())
    throw nurbs::InputError(
        "prior spring fit: one prior stiffness per spring (and per volume term) expected");
  for (double k : options.prior)
    if (!(k > 0.0) || !std::isfinite(k))
      throw nurbs::InputError("prior spring fit: prior stiffnesses must be positive and finite");
  if (!(options.weight >= 0.0)) throw nurbs::InputError("prior spring fit: weight must be >= 0");
  if (data.loads.size() != data.references.size() || data.loads.empty())
    throw nurbs::InputError("prior spring fit: one reference per load case, at least one case");

  auto* objective = new PriorObjective(data, options.prior, options.weight);
  ceres::GradientProblem problem(objective);  // takes ownership
  std::vector<double> theta;
  for (double k : options.prior) theta.push_back(std::log(k));
  {
    double cost = 0.0;
    if (!objective->Evaluate(theta.data(), &cost, nullptr))
      throw std::runtime_error("prior spring fit: the network is singular at the prior");
  }
  ceres::GradientProblemSolver::Options solver_options;
  solver_options.line_search_direction_type = ceres::LBFGS;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.function_tolerance = options.function_tolerance;
  solver_options.gradient_tolerance = 1e-12;
  solver_options.parameter_tolerance = 1e-10;
  ceres::GradientProblemSolver::Summary summary;
  {
    // L-BFGS's Wolfe line search logs a warning whenever it settles for an Armijo point, which
    // happens routinely near the optimum of these badly scaled problems; the summary keeps the
    // outcome.
    const int level = FLAGS_minloglevel;
    FLAGS_minloglevel = google::GLOG_ERROR;
    ceres::Solve(solver_options, problem, theta.data(), &summary);
    FLAGS_minloglevel = level;
  }

  PriorSpringFitResult result;
  const size_t springs = data.network.springs.size();
  for (size_t s = 0; s < theta.size(); ++s)
    (s < springs ? result.spring_stiffness : result.volume_modulus).push_back(std::exp(theta[s]));
  // Final metrics at the returned parameters (Ceres' last evaluation may be a rejected trial).
  const Grouping one = one_group_per_spring(data.network);
  Eigen::VectorXd residuals;
  if (!displacement_residuals(
          data, one,
          Eigen::Map<Eigen::VectorXd>(theta.data(), static_cast<Eigen::Index>(theta.size())),
          residuals, nullptr))
    throw std::runtime_error("prior spring fit: the fitted network is singular");
  const int rows =
      static_cast<int>(residuals.size() / static_cast<Eigen::Index>(data.loads.size()));
  const int dim = data.network.dimension;
  for (size_t c = 0; c < data.loads.size(); ++c) {
    const Eigen::VectorXd r = residuals.segment(static_cast<Eigen::Index>(c) * rows, rows);
    result.percent_e_rms.push_back(100.0 * r.norm());
    // r_a = (u_a - u_ref,a) / (o_max sqrt(n)): the largest node error over o_max is sqrt(n)
    // max|r_a|.
    double largest = 0.0;
    for (int a = 0; a < rows / dim; ++a)
      largest = std::max(largest, r.segment(a * dim, dim).norm());
    result.percent_e_max.push_back(100.0 * largest * std::sqrt(static_cast<double>(rows / dim)));
  }
  result.cost = summary.final_cost;
  result.iterations = static_cast<int>(summary.iterations.size());
  result.converged = summary.termination_type == ceres::CONVERGENCE;
  result.message = summary.message;
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace isospring::fitting
