// calibrate()'s last stages: a network's errors against the IGA reference on the fitted and
// held-out load cases, and the matrix approach's models measured the same way.
#include <algorithm>
#include <stdexcept>

#include "isospring/analysis/spring_static.hpp"
#include "nmsm/calibration_stages.hpp"

namespace isospring::fitting::detail {

namespace {

std::vector<std::vector<Eigen::Vector3d>> per_patch(
    const analysis::DofMap& dofs, const std::vector<Eigen::Vector3d>& node_values) {
  std::vector<std::vector<Eigen::Vector3d>> result(static_cast<size_t>(dofs.num_patches()));
  for (int p = 0; p < dofs.num_patches(); ++p)
    for (int node : dofs.patch_nodes(p)) result[p].push_back(node_values[node]);
  return result;
}

}  // namespace

std::vector<Eigen::Vector3d> to_points(const Eigen::VectorXd& flat, int dim) {
  std::vector<Eigen::Vector3d> points(static_cast<size_t>(flat.size() / dim),
                                      Eigen::Vector3d::Zero());
  for (size_t a = 0; a < points.size(); ++a)
    for (int c = 0; c < dim; ++c) points[a][c] = flat[static_cast<Eigen::Index>(a) * dim + c];
  return points;
}

analysis::SpringLinearSolver network_solver(const FitSetup& setup,
                                            const analysis::SpringNetwork& network) {
  return analysis::SpringLinearSolver(network, setup.data.constrained_dofs);
}

std::vector<Eigen::Vector3d> model_points(const FitSetup& setup,
                                          const analysis::SpringLinearSolver& solver, int c) {
  const int dim = setup.dim;
  const Eigen::VectorXd u = solver.solve(setup.loads[c]).displacement;
  const int nodes = static_cast<int>(setup.particle_of_node.size());
  Eigen::VectorXd node_u(static_cast<Eigen::Index>(nodes) * dim);
  for (int a = 0; a < nodes; ++a)
    node_u.segment(a * dim, dim) = u.segment(setup.particle_of_node[a] * dim, dim);
  return to_points(node_u, dim);
}

void evaluate_cases(const analysis::Problem& problem, const CalibrationSettings& settings,
                    const FitSetup& setup, const std::vector<std::array<bool, 6>>& inner,
                    const analysis::SpringNetwork& network, std::vector<CaseErrors>& fit_errors,
                    std::vector<CaseErrors>& holdout_errors) {
  const std::vector<int>& fitted = setup.fitted;
  const std::vector<int>& held_out = setup.held_out;
  const analysis::SpringLinearSolver solver = network_solver(setup, network);
  for (size_t c = 0; c < problem.load_cases.size(); ++c) {
    const bool is_fit =
        std::find(fitted.begin(), fitted.end(), static_cast<int>(c)) != fitted.end();
    const bool is_holdout =
        std::find(held_out.begin(), held_out.end(), static_cast<int>(c)) != held_out.end();
    if (!is_fit && !is_holdout) continue;
    const auto ref_points = to_points(setup.reference.load_cases[c].displacement, setup.dim);
    const auto model = model_points(setup, solver, static_cast<int>(c));
    CaseErrors errors;
    errors.id = problem.load_cases[c].id;
    errors.control = error_metrics(ref_points, model);
    if (settings.field_metrics) {
      const auto ref_per_patch = per_patch(*setup.dofs, ref_points);
      const auto model_per_patch = per_patch(*setup.dofs, model);
      errors.field = field_error_metrics(problem.patches, ref_per_patch, model_per_patch,
                                         settings.field_samples);
      errors.surface = surface_error_metrics(problem.patches, ref_per_patch, model_per_patch,
                                             settings.field_samples, inner);
    }
    for (size_t a = 0; a < ref_points.size(); ++a)
      errors.node_error.push_back(model[a] - ref_points[a]);
    (is_fit ? fit_errors : holdout_errors).push_back(std::move(errors));
  }
}

std::vector<MatrixComparison> compare_matrix_approach(const analysis::Problem& problem,
                                                      const CalibrationSettings& settings,
                                                      const FitSetup& setup,
                                                      const std::vector<std::array<bool, 6>>& inner,
                                                      const SpringMesh& mesh,
                                                      const Grouping& grouping) {
  std::vector<MatrixComparison> comparisons;
  // The calibrated network (masses, supports, damping) with the matrix fit's springs; a
  // singular one is reported unsolved.
  auto compare = [&](const std::string& method, const MatrixFitResult& fit) {
    MatrixComparison comparison;
    comparison.method = method;
    comparison.fit = fit;
    analysis::SpringNetwork network = mesh.network;
    for (size_t s = 0; s < network.springs.size(); ++s)
      network.springs[s].stiffness = fit.spring_stiffness[s];
    try {
      evaluate_cases(problem, settings, setup, inner, network, comparison.fit_cases,
                     comparison.holdout);
      comparison.solved = true;
    } catch (const std::runtime_error&) {
      comparison.fit_cases.clear();
      comparison.holdout.clear();
    }
    comparisons.push_back(std::move(comparison));
  };
  compare("global", fit_stiffness_matrix(problem, mesh, grouping));
  bool linear = true;
  for (const auto& patch : problem.patches)
    for (int d = 0; d < patch.param_dim(); ++d) linear = linear && patch.degree(d) == 1;
  if (linear) compare("per_element", fit_stiffness_matrix_per_element(problem, mesh));
  return comparisons;
}

}  // namespace isospring::fitting::detail
