// The acceleration objective [S15 4.1-4.5]: bound-constrained linear least squares in k.
#include "isospring/fitting/acceleration_fit.hpp"

#include <Eigen/QR>
#include <algorithm>
#include <chrono>
#include <cmath>

#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/constraints.hpp"
#include "isospring/analysis/dof_map.hpp"
#include "isospring/analysis/spring_static.hpp"
#include "isospring/analysis/static_solver.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::fitting {

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Least-squares solution on the columns `passive` (zero elsewhere).
Eigen::VectorXd solve_on(const Eigen::MatrixXd& a, const Eigen::VectorXd& b,
                         const std::vector<Eigen::Index>& passive) {
  Eigen::MatrixXd sub(a.rows(), static_cast<Eigen::Index>(passive.size()));
  for (size_t c = 0; c < passive.size(); ++c)
    sub.col(static_cast<Eigen::Index>(c)) = a.col(passive[c]);
  const Eigen::VectorXd y = sub.colPivHouseholderQr().solve(b);
  Eigen::VectorXd z = Eigen::VectorXd::Zero(a.cols());
  for (size_t c = 0; c < passive.size(); ++c) z[passive[c]] = y[static_cast<Eigen::Index>(c)];
  return z;
}

}  // namespace

Eigen::VectorXd nonnegative_least_squares(const Eigen::MatrixXd& a_in, const Eigen::VectorXd& b) {
  if (a_in.rows() != b.size())
    throw nurbs::InputError("nonnegative_least_squares: A has " + std::to_string(a_in.rows()) +
                            " rows but b has " + std::to_string(b.size()));
  const Eigen::Index n = a_in.cols();
  // Unit columns: the stationarity test w_j > tol then compares like with like.
  Eigen::VectorXd scale = a_in.colwise().norm().transpose();
  for (Eigen::Index j = 0; j < n; ++j)
    if (!(scale[j] > 0.0)) scale[j] = 1.0;
  const Eigen::MatrixXd a = a_in * scale.cwiseInverse().asDiagonal();
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  std::vector<bool> in_passive(static_cast<size_t>(n), false);
  // Tolerance on the dual variables: round-off of A^T r with unit columns.
  const double tol = 10.0 * std::numeric_limits<double>::epsilon() * static_cast<double>(n + 1) *
                     std::max(b.norm(), 1e-300);
  for (int outer = 0; outer < 3 * n + 10; ++outer) {
    const Eigen::VectorXd w = a.transpose() * (b - a * x);
    Eigen::Index t = -1;
    for (Eigen::Index j = 0; j < n; ++j)
      if (!in_passive[static_cast<size_t>(j)] && w[j] > tol && (t < 0 || w[j] > w[t])) t = j;
    if (t < 0) break;  // KKT: every zero variable has a non-positive gradient of the gain
    in_passive[static_cast<size_t>(t)] = true;
    for (int inner = 0; inner <= n; ++inner) {
      std::vector<Eigen::Index> passive;
      for (Eigen::Index j = 0; j < n; ++j)
        if (in_passive[static_cast<size_t>(j)]) passive.push_back(j);
      const Eigen::VectorXd z = solve_on(a, b, passive);
      bool feasible = true;
      for (Eigen::Index j : passive) feasible = feasible && z[j] > 0.0;
      if (feasible) {
        x = z;
        break;
      }
      // Step from x towards z until the first passive variable reaches zero; drop it.
      double alpha = 1.0;
      for (Eigen::Index j : passive)
        if (z[j] <= 0.0) alpha = std::min(alpha, x[j] / (x[j] - z[j]));
      x += alpha * (z - x);
      for (Eigen::Index j : passive)
        if (x[j] <= 0.0 || (z[j] <= 0.0 && x[j] <= 1e-14 * x.cwiseAbs().maxCoeff())) {
          in_passive[static_cast<size_t>(j)] = false;
          x[j] = 0.0;
        }
    }
  }
  return x.cwiseQuotient(scale);
}

AccelerationFitResult fit_accelerations(const DisplacementFitData& data,
                                        const AccelerationFitOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const analysis::SpringNetwork& network = data.network;
  const int dim = network.dimension;
  const auto num_particles = static_cast<Eigen::Index>(network.positions.size());
  const Grouping& grouping = options.grouping;
  if (grouping.group_of_spring.size() != network.springs.size())
    throw nurbs::InputError("fit_accelerations: the grouping has " +
                            std::to_string(grouping.group_of_spring.size()) +
                            " springs, the network " + std::to_string(network.springs.size()));
  if (data.loads.size() != data.references.size() || data.loads.empty())
    throw nurbs::InputError("fit_accelerations: one load and one reference per case expected");
  if (options.weight_by_mass && (network.masses.size() != network.positions.size() ||
                                 std::any_of(network.masses.begin(), network.masses.end(),
                                             [](double m) { return !(m > 0); })))
    throw nurbs::InputError(
        "fit_accelerations: every particle needs a positive mass for the acceleration "
        "residual (assign masses, or weight by force instead)");

  // Free particle DOFs -> rows of one case.
  std::vector<Eigen::Index> row(static_cast<size_t>(num_particles * dim), -1);
  std::vector<bool> held(row.size(), false);
  for (Eigen::Index p = 0; p < num_particles; ++p)
    if (!network.fixed.empty() && network.fixed[static_cast<size_t>(p)])
      for (int c = 0; c < dim; ++c) held[static_cast<size_t>(p * dim + c)] = true;
  for (int d : data.constrained_dofs) held[static_cast<size_t>(d)] = true;
  Eigen::Index free_rows = 0;
  for (size_t d = 0; d < row.size(); ++d)
    if (!held[d]) row[d] = free_rows++;

  const auto cases = static_cast<Eigen::Index>(data.loads.size());
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(cases * free_rows, grouping.num_groups());
  Eigen::VectorXd b(cases * free_rows);
  for (Eigen::Index c = 0; c < cases; ++c) {
    const Eigen::VectorXd& ref = data.references[static_cast<size_t>(c)];
    const Eigen::VectorXd& load = data.loads[static_cast<size_t>(c)];
    if (load.size() != num_particles * dim ||
        ref.size() != static_cast<Eigen::Index>(data.particle_of_node.size()) * dim)
      throw nurbs::InputError("fit_accelerations: load or reference of case " + std::to_string(c) +
                              " has the wrong size");
    Eigen::VectorXd u = Eigen::VectorXd::Zero(num_particles * dim);
    for (size_t node = 0; node < data.particle_of_node.size(); ++node)
      u.segment(data.particle_of_node[node] * dim, dim) =
          ref.segment(static_cast<Eigen::Index>(node) * dim, dim);
    const Eigen::Index offset = c * free_rows;
    for (size_t d = 0; d < row.size(); ++d)
      if (row[d] >= 0) b[offset + row[d]] = load[static_cast<Eigen::Index>(d)];
    for (size_t s = 0; s < network.springs.size(); ++s) {
      const analysis::Spring& spring = network.springs[s];
      const Eigen::VectorXd n = (network.positions[static_cast<size_t>(spring.i)] -
                                 network.positions[static_cast<size_t>(spring.j)])
                                    .head(dim)
                                    .normalized();
      // (K u)_i = k n n^T (u_i - u_j), (K u)_j = -(K u)_i.
      const double stretch = n.dot(u.segment(spring.i * dim, dim) - u.segment(spring.j * dim, dim));
      const int g = grouping.group_of_spring[s];
      for (int k = 0; k < dim; ++k) {
        const Eigen::Index ri = row[static_cast<size_t>(spring.i * dim + k)];
        const Eigen::Index rj = row[static_cast<size_t>(spring.j * dim + k)];
        if (ri >= 0) a(offset + ri, g) += n[k] * stretch;
        if (rj >= 0) a(offset + rj, g) -= n[k] * stretch;
      }
    }
  }
  if (options.weight_by_mass)
    for (size_t d = 0; d < row.size(); ++d)
      if (row[d] >= 0) {
        const double w = 1.0 / network.masses[d / static_cast<size_t>(dim)];
        for (Eigen::Index c = 0; c < cases; ++c) {
          a.row(c * free_rows + row[d]) *= w;
          b[c * free_rows + row[d]] *= w;
        }
      }

  AccelerationFitResult result;
  const Eigen::VectorXd k = nonnegative_least_squares(a, b);
  result.relative_residual = (a * k - b).norm() / b.norm();
  for (Eigen::Index g = 0; g < k.size(); ++g) {
    result.group_stiffness.push_back(k[g]);
    if (k[g] == 0.0) ++result.groups_at_zero;
  }
  for (int g : grouping.group_of_spring) result.spring_stiffness.push_back(k[g]);
  result.seconds = seconds_since(start);
  return result;
}

MatrixComparison acceleration_baseline(const analysis::Problem& problem,
                                       const CalibrationSettings& settings,
                                       const CalibrationResult& calibrated) {
  const auto start = std::chrono::steady_clock::now();
  const analysis::DofMap dofs(problem);
  const int dim = dofs.dofs_per_node();
  const SpringMesh& mesh = calibrated.mesh;
  DisplacementFitData data;
  data.network = mesh.network;
  data.particle_of_node = particle_of_node(problem, mesh);
  // Single held components (fully held particles are mesh.network.fixed already).
  for (int d : analysis::build_constraints(problem, dofs).dofs) {
    const int particle = data.particle_of_node[static_cast<size_t>(d / dim)];
    if (!mesh.network.fixed[static_cast<size_t>(particle)])
      data.constrained_dofs.push_back(particle * dim + d % dim);
  }
  std::sort(data.constrained_dofs.begin(), data.constrained_dofs.end());
  data.constrained_dofs.erase(
      std::unique(data.constrained_dofs.begin(), data.constrained_dofs.end()),
      data.constrained_dofs.end());

  analysis::StaticResult reference;
  if (settings.reference_displacements.empty()) {
    reference = analysis::solve_static(problem);
  } else {
    for (size_t c = 0; c < problem.load_cases.size(); ++c) {
      analysis::LoadCaseResult given;
      given.displacement = settings.reference_displacements[c];
      reference.load_cases.push_back(given);
    }
  }
  const auto num_particles = static_cast<Eigen::Index>(mesh.network.positions.size());
  std::vector<Eigen::VectorXd> loads;
  for (const auto& lc : problem.load_cases) {
    const Eigen::VectorXd node_load = analysis::assemble_load(problem, dofs, lc);
    Eigen::VectorXd f = Eigen::VectorXd::Zero(num_particles * dim);
    for (size_t a = 0; a < data.particle_of_node.size(); ++a)
      f.segment(data.particle_of_node[a] * dim, dim) +=
          node_load.segment(static_cast<Eigen::Index>(a) * dim, dim);
    loads.push_back(f);
  }
  // The same fitted / held-out split as the calibration (ids were validated there).
  auto listed = [](const std::vector<std::string>& list, const std::string& id) {
    return std::find(list.begin(), list.end(), id) != list.end();
  };
  std::vector<size_t> fitted, held_out;
  for (size_t c = 0; c < problem.load_cases.size(); ++c) {
    const std::string& id = problem.load_cases[c].id;
    const bool holdout = listed(settings.holdout_cases, id);
    if (settings.fit_cases.empty() ? !holdout : listed(settings.fit_cases, id))
      fitted.push_back(c);
    else if (holdout)
      held_out.push_back(c);
  }
  for (size_t c : fitted) {
    data.loads.push_back(loads[c]);
    data.references.push_back(reference.load_cases[c].displacement);
  }
  AccelerationFitOptions options;
  // A per-spring calibration is compared on the rest-length grouping it started from: per
  // spring, the active-set solve (dense, one QR per step) would cost minutes at 2000 springs, and
  // the acceleration objective is a baseline, not the model.
  options.grouping = settings.per_spring ? group_by_rest_length(mesh.network, calibrated.gamma)
                                         : calibrated.grouping;
  const AccelerationFitResult fit = fit_accelerations(data, options);

  MatrixComparison comparison;
  comparison.method = "acceleration";
  comparison.fit.group_stiffness = fit.group_stiffness;
  comparison.fit.spring_stiffness = fit.spring_stiffness;
  comparison.fit.relative_residual = fit.relative_residual;
  comparison.fit.negative_springs =
      static_cast<int>(std::count(fit.spring_stiffness.begin(), fit.spring_stiffness.end(), 0.0));
  analysis::SpringNetwork network = mesh.network;
  for (size_t s = 0; s < network.springs.size(); ++s)
    network.springs[s].stiffness = fit.spring_stiffness[s];
  auto to_points = [dim](const Eigen::VectorXd& flat) {
    std::vector<Eigen::Vector3d> points(static_cast<size_t>(flat.size() / dim),
                                        Eigen::Vector3d::Zero());
    for (size_t a = 0; a < points.size(); ++a)
      for (int c = 0; c < dim; ++c) points[a][c] = flat[static_cast<Eigen::Index>(a) * dim + c];
    return points;
  };
  try {
    for (int pass = 0; pass < 2; ++pass)
      for (size_t c : pass == 0 ? fitted : held_out) {
        const Eigen::VectorXd u =
            analysis::solve_spring_linear(network, loads[c], data.constrained_dofs).displacement;
        Eigen::VectorXd node_u(dofs.num_dofs());
        for (int a = 0; a < dofs.num_nodes(); ++a)
          node_u.segment(a * dim, dim) = u.segment(data.particle_of_node[a] * dim, dim);
        CaseErrors errors;
        errors.id = problem.load_cases[c].id;
        errors.control =
            error_metrics(to_points(reference.load_cases[c].displacement), to_points(node_u));
        (pass == 0 ? comparison.fit_cases : comparison.holdout).push_back(std::move(errors));
      }
    comparison.solved = true;
  } catch (const std::runtime_error&) {
    // Springs held at k = 0 can leave a mechanism: reported as unsolved, as the matrix approach.
    comparison.fit_cases.clear();
    comparison.holdout.clear();
  }
  comparison.fit.seconds = seconds_since(start);
  return comparison;
}

}  // namespace isospring::fitting
