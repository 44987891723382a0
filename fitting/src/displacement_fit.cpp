// Displacement-objective calibration: residuals with an analytic Jacobian, wrapped for Ceres.
#include "isospring/fitting/displacement_fit.hpp"

#include <ceres/ceres.h>

#include <Eigen/SparseCholesky>
#include <chrono>
#include <cmath>
#include <memory>
#include <stdexcept>

#include "isospring/analysis/spring_mechanics.hpp"
#include "isospring/analysis/spring_static.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::fitting {

namespace {

int num_nodes(const DisplacementFitData& data) {
  return static_cast<int>(data.particle_of_node.size());
}

// 1 / (o_max sqrt(n)) of a case: residuals then square-sum to (%e_rms / 100)^2.
double case_scale(const DisplacementFitData& data, const Eigen::VectorXd& reference) {
  const int dim = data.network.dimension;
  double o_max = 0.0;
  for (int a = 0; a < num_nodes(data); ++a)
    o_max = std::max(o_max, reference.segment(a * dim, dim).norm());
  return 1.0 / (o_max * std::sqrt(static_cast<double>(num_nodes(data))));
}

analysis::SpringNetwork with_group_stiffness(const DisplacementFitData& data,
                                             const Grouping& grouping,
                                             const Eigen::VectorXd& stiffness) {
  analysis::SpringNetwork net = data.network;
  for (size_t s = 0; s < net.springs.size(); ++s)
    net.springs[s].stiffness = stiffness[grouping.group_of_spring[s]];
  return net;
}

void check_data(const DisplacementFitData& data, const Grouping& grouping) {
  const int dim = data.network.dimension;
  const auto particle_dofs = static_cast<Eigen::Index>(data.network.positions.size()) * dim;
  if (data.loads.empty() || data.loads.size() != data.references.size())
    throw nurbs::InputError("calibration: give at least one load case with a reference");
  if (grouping.group_of_spring.size() != data.network.springs.size() || grouping.num_groups() == 0)
    throw nurbs::InputError("calibration: the stiffness grouping does not cover every spring");
  for (size_t c = 0; c < data.loads.size(); ++c) {
    if (data.loads[c].size() != particle_dofs ||
        data.references[c].size() != static_cast<Eigen::Index>(num_nodes(data)) * dim)
      throw nurbs::InputError("calibration: load case " + std::to_string(c) +
                              " has loads or reference displacements of the wrong size");
    if (!(data.references[c].cwiseAbs().maxCoeff() > 0.0) || !data.references[c].allFinite())
      throw nurbs::InputError("calibration: load case " + std::to_string(c) +
                              " has a zero or non-finite reference displacement; every fitted "
                              "load case must load the part");
  }
}

class DisplacementCost : public ceres::CostFunction {
 public:
  DisplacementCost(const DisplacementFitData& data, const Grouping& grouping)
      : data_(data), grouping_(grouping) {
    set_num_residuals(num_displacement_residuals(data));
    for (int g = 0; g < grouping.num_groups(); ++g) mutable_parameter_block_sizes()->push_back(1);
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const int groups = grouping_.num_groups();
    Eigen::VectorXd theta(groups);
    for (int g = 0; g < groups; ++g) theta[g] = parameters[g][0];
    Eigen::VectorXd r;
    Eigen::MatrixXd j;
    if (!displacement_residuals(data_, grouping_, theta, r, jacobians ? &j : nullptr)) return false;
    Eigen::Map<Eigen::VectorXd>(residuals, r.size()) = r;
    if (jacobians)
      for (int g = 0; g < groups; ++g)
        if (jacobians[g]) Eigen::Map<Eigen::VectorXd>(jacobians[g], r.size()) = j.col(g);
    return true;
  }

 private:
  const DisplacementFitData& data_;
  const Grouping& grouping_;
};

// sqrt(w) (theta_s - phi_a): pulls a spring's log-stiffness towards its group's shared value.
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
Eigen::VectorXd initial_stiffness(const DisplacementFitData& data, const Grouping& grouping,
                                  double youngs_modulus) {
  Eigen::VectorXd k(grouping.num_groups());
  for (int g = 0; g < grouping.num_groups(); ++g) k[g] = youngs_modulus * grouping.centre[g];
  Eigen::VectorXd r;
  if (!displacement_residuals(data, grouping, k.array().log().matrix(), r, nullptr))
    throw std::runtime_error("calibration: the spring network is a mechanism under the supports");
  // r = s (u - u_ref): recover s u and s u_ref per case and solve min |s (u / a - u_ref)|^2.
  const int dim = data.network.dimension;
  double uu = 0.0, ur = 0.0;
  Eigen::Index row = 0;
  for (const auto& reference : data.references) {
    const double scale = case_scale(data, reference);
    for (int a = 0; a < num_nodes(data) * dim; ++a, ++row) {
      const double su = r[row] + scale * reference[a], sr = scale * reference[a];
      uu += su * su;
      ur += su * sr;
    }
  }
  if (ur > 0.0) k *= uu / ur;
  return k;
}

// Forwards Ceres' per-iteration summary to the caller's progress function.
class IterationReporter : public ceres::IterationCallback {
 public:
  explicit IterationReporter(const std::function<void(int, double)>& report) : report_(report) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& summary) override {
    report_(summary.iteration, summary.cost);
    return ceres::SOLVER_CONTINUE;
  }

 private:
  const std::function<void(int, double)>& report_;
};

}  // namespace

int num_displacement_residuals(const DisplacementFitData& data) {
  return static_cast<int>(data.references.size()) * num_nodes(data) * data.network.dimension;
}

bool displacement_residuals(const DisplacementFitData& data, const Grouping& grouping,
                            const Eigen::VectorXd& theta, Eigen::VectorXd& residuals,
                            Eigen::MatrixXd* jacobian) {
  const int dim = data.network.dimension;
  const int groups = grouping.num_groups();
  const Eigen::VectorXd k = theta.array().exp().matrix();
  const analysis::SpringNetwork net = with_group_stiffness(data, grouping, k);
  const int particle_dofs = static_cast<int>(net.positions.size()) * dim;
  const analysis::FreeDofSet dofs(particle_dofs,
                                  analysis::constrained_dofs(net, data.constrained_dofs));
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(
      dofs.restrict(analysis::rest_stiffness(net)));
  if (solver.info() != Eigen::Success || (solver.vectorD().array() <= 0.0).any()) return false;

  // Unit rest direction of every spring (the non-zero part of g_s).
  std::vector<Eigen::Vector3d> direction(net.springs.size());
  for (size_t s = 0; s < net.springs.size(); ++s) {
    Eigen::Vector3d l = net.positions[net.springs[s].i] - net.positions[net.springs[s].j];
    if (dim == 2) l.z() = 0.0;
    direction[s] = l.normalized();
  }

  const int rows_per_case = num_nodes(data) * dim;
  const auto cases = static_cast<int>(data.loads.size());
  residuals.resize(static_cast<Eigen::Index>(cases) * rows_per_case);
  if (jacobian) jacobian->setZero(residuals.size(), groups);
  // Adjoint form when the parameters outnumber the free DOFs: K^-1 once, then products.
  const bool use_inverse = jacobian && groups * cases > dofs.num_free();
  Eigen::MatrixXd inverse;
  if (use_inverse)
    inverse = solver.solve(Eigen::MatrixXd::Identity(dofs.num_free(), dofs.num_free()));

  for (int c = 0; c < cases; ++c) {
    const Eigen::VectorXd u = dofs.expand(solver.solve(dofs.restrict(data.loads[c])));
    const Eigen::VectorXd& reference = data.references[c];
    const double scale = case_scale(data, reference);
    const Eigen::Index offset = static_cast<Eigen::Index>(c) * rows_per_case;
    for (int a = 0; a < num_nodes(data); ++a)
      for (int d = 0; d < dim; ++d)
        residuals[offset + a * dim + d] =
            scale * (u[data.particle_of_node[a] * dim + d] - reference[a * dim + d]);
    if (!jacobian) continue;

    // dK/dtheta_g u = sum_{s in g} k_s g_s (g_s^T u), on the free DOFs.
    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(net.springs.size() * 2 * static_cast<size_t>(dim));
    for (size_t s = 0; s < net.springs.size(); ++s) {
      const auto& spring = net.springs[s];
      const Eigen::Vector3d& n = direction[s];
      double stretch = 0.0;
      for (int d = 0; d < dim; ++d)
        stretch += n[d] * (u[spring.i * dim + d] - u[spring.j * dim + d]);
      const double factor = spring.stiffness * stretch;
      const int g = grouping.group_of_spring[s];
      for (int d = 0; d < dim; ++d) {
        const int fi = dofs.free_index(spring.i * dim + d),
                  fj = dofs.free_index(spring.j * dim + d);
        if (fi >= 0) entries.emplace_back(fi, g, factor * n[d]);
        if (fj >= 0) entries.emplace_back(fj, g, -factor * n[d]);
      }
    }
    Eigen::SparseMatrix<double> rhs(dofs.num_free(), groups);
    rhs.setFromTriplets(entries.begin(), entries.end());
    // du/dtheta = -K^-1 (dK/dtheta u).
    const Eigen::MatrixXd du = use_inverse ? Eigen::MatrixXd(inverse * rhs)
                                           : Eigen::MatrixXd(solver.solve(Eigen::MatrixXd(rhs)));
    for (int a = 0; a < num_nodes(data); ++a)
      for (int d = 0; d < dim; ++d) {
        const int f = dofs.free_index(data.particle_of_node[a] * dim + d);
        if (f >= 0) jacobian->row(offset + a * dim + d) = -scale * du.row(f);
      }
  }
  return true;
}

DisplacementFitResult fit_displacements(const DisplacementFitData& data,
                                        const DisplacementFitOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const Grouping& grouping = options.grouping;
  check_data(data, grouping);
  const int groups = grouping.num_groups();
  Eigen::VectorXd k0 = options.initial.empty()
                           ? initial_stiffness(data, grouping, options.youngs_modulus)
                           : Eigen::Map<const Eigen::VectorXd>(options.initial.data(), groups);
  const double log_floor = std::log(options.min_stiffness_ratio * k0.maxCoeff());
  std::vector<double> theta(static_cast<size_t>(groups));
  for (int g = 0; g < groups; ++g) {
    double k = k0[g];
    if (!options.upper_bounds.empty()) k = std::min(k, 0.5 * options.upper_bounds[g]);
    theta[g] = std::max(std::log(k), log_floor);
  }

  ceres::Problem problem;
  std::vector<double*> blocks;
  for (auto& t : theta) blocks.push_back(&t);
  problem.AddResidualBlock(new DisplacementCost(data, grouping), nullptr, blocks);
  for (int g = 0; g < groups && !options.upper_bounds.empty(); ++g)
    problem.SetParameterUpperBound(blocks[g], 0, std::log(options.upper_bounds[g]));
  for (int g = 0; g < groups; ++g) problem.SetParameterLowerBound(blocks[g], 0, log_floor);
  std::vector<double> shared;
  if (options.regularization > 0.0) {
    const Grouping& reg = options.regularization_groups;
    shared.assign(static_cast<size_t>(reg.num_groups()), 0.0);
    std::vector<int> members(shared.size(), 0);
    for (int g = 0; g < groups; ++g) {
      shared[reg.group_of_spring[g]] += theta[g];
      ++members[reg.group_of_spring[g]];
    }
    for (size_t a = 0; a < shared.size(); ++a) shared[a] /= std::max(1, members[a]);
    for (int g = 0; g < groups; ++g)
      problem.AddResidualBlock(new EqualityRegularization(options.regularization), nullptr,
                               &theta[g], &shared[reg.group_of_spring[g]]);
  }

  ceres::Solver::Options solver_options;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.function_tolerance = 1e-12;
  solver_options.gradient_tolerance = 1e-14;
  solver_options.parameter_tolerance = 1e-12;
  solver_options.num_threads = 1;
  if (groups > 64) {
    // Many parameters: the Jacobian is dense, so normal equations would cost P^3 per iteration;
    // conjugate gradients only need Jacobian products.
    solver_options.linear_solver_type = ceres::CGNR;
    solver_options.preconditioner_type = ceres::JACOBI;
  } else {
    solver_options.linear_solver_type = ceres::DENSE_QR;
  }
  IterationReporter reporter(options.on_iteration);
  if (options.on_iteration) solver_options.callbacks.push_back(&reporter);
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);

  DisplacementFitResult result;
  result.iterations = static_cast<int>(summary.iterations.size()) - 1;
  result.cost = summary.final_cost;
  result.converged = summary.termination_type == ceres::CONVERGENCE;
  result.message = summary.message;
  for (int g = 0; g < groups; ++g) {
    result.group_stiffness.push_back(std::exp(theta[g]));
    // Within 1e-9 in log: the bound is active (Ceres projects onto it exactly).
    if (theta[g] <= log_floor + 1e-9) ++result.groups_at_lower_bound;
  }
  for (int g : grouping.group_of_spring)
    result.spring_stiffness.push_back(result.group_stiffness[g]);
  Eigen::VectorXd r;
  Eigen::VectorXd final_theta = Eigen::Map<Eigen::VectorXd>(theta.data(), groups);
  if (!displacement_residuals(data, grouping, final_theta, r, nullptr))
    throw std::runtime_error("calibration: the fitted spring network is a mechanism");
  const int rows = num_nodes(data) * data.network.dimension;
  for (size_t c = 0; c < data.references.size(); ++c)
    result.percent_e_rms.push_back(100.0 *
                                   r.segment(static_cast<Eigen::Index>(c) * rows, rows).norm());
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace isospring::fitting
