// The reduced model of the frontier's most accurate kind (frontier_stages.hpp): basis, static
// held-out errors, measured step.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "frontier_stages.hpp"
#include "isospring/analysis/spring_reduced_model.hpp"
#include "isospring/analysis/spring_static.hpp"
#include "isospring/fitting/error_metrics.hpp"
#include "isospring/fitting/spring_mesh.hpp"
#include "isospring/workflows/runtime_step_timing.hpp"

namespace isospring::workflows::frontier {

namespace {

std::vector<Eigen::Vector3d> node_points(const Eigen::VectorXd& flat,
                                         const std::vector<int>& particle_of_node, int dim) {
  std::vector<Eigen::Vector3d> points(particle_of_node.size(), Eigen::Vector3d::Zero());
  for (size_t a = 0; a < points.size(); ++a)
    for (int c = 0; c < dim; ++c) points[a][c] = flat[particle_of_node[a] * dim + c];
  return points;
}

size_t load_index(const fitting::CalibrationResult& r, const std::string& id) {
  const auto it = std::find(r.load_ids.begin(), r.load_ids.end(), id);
  if (it == r.load_ids.end()) throw std::runtime_error("reduced model: no load case " + id);
  return static_cast<size_t>(it - r.load_ids.begin());
}

// Worst %e_rms over `cases` of the reduced model's static response u = Phi Lambda^-1 Phi^T f.
// The full network's own response is measured the same way and must reproduce the
// calibration's error (else the network alone is not the calibrated model, e.g. supports on
// single components the network's fixed particles do not carry, and the comparison would lie).
double worst_reduced_error(const ObjectSetup& setup, const fitting::CalibrationResult& r,
                           const analysis::ReducedSpringModel& reduced,
                           const std::vector<int>& particle_of_node,
                           const std::vector<fitting::CaseErrors>& cases, std::string* worst_id) {
  const int dim = r.mesh.network.dimension;
  double worst = 0.0;
  for (const fitting::CaseErrors& e : cases) {
    const size_t c = load_index(r, e.id);
    const Eigen::VectorXd& f = r.particle_loads[c];
    std::vector<Eigen::Vector3d> reference(particle_of_node.size(), Eigen::Vector3d::Zero());
    for (size_t a = 0; a < reference.size(); ++a)
      for (int k = 0; k < dim; ++k)
        reference[a][k] = setup.reference[c][static_cast<Eigen::Index>(a) * dim + k];
    const Eigen::VectorXd full = analysis::solve_spring_linear(r.mesh.network, f).displacement;
    const double full_error =
        fitting::error_metrics(reference, node_points(full, particle_of_node, dim)).percent_e_rms;
    if (std::abs(full_error - e.control.percent_e_rms) > 1e-6 * (1.0 + e.control.percent_e_rms))
      throw std::runtime_error(
          "reduced model: the network alone does not reproduce the calibrated error on " + e.id +
          " (supports on single components?)");
    const double error =
        fitting::error_metrics(reference,
                               node_points(reduced.static_displacement(f), particle_of_node, dim))
            .percent_e_rms;
    if (error >= worst) {
      worst = error;
      if (worst_id) *worst_id = e.id;
    }
  }
  return worst;
}

}  // namespace

FrontierRow reduced_row(const ObjectSetup& setup, const fitting::CalibrationResult& best,
                        const FrontierRow& best_row, const FrontierOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  FrontierRow row;
  row.kind = {"reduced", false, false, 0, true};
  row.reduced_of = best_row.kind.name;
  row.reach = best_row.reach;
  row.gamma = best_row.gamma;
  row.prior_weight = best_row.prior_weight;
  row.parameters = best_row.parameters;
  row.cross_validation_worst = NAN;  // nothing was chosen by cross-validation
  row.estimated_step_us = NAN;       // step_cost.hpp estimates networks only
  const analysis::SpringNetwork& network = best.mesh.network;
  analysis::ReducedModelOptions reduced_options;
  for (const std::string& id : setup.suite.training)
    reduced_options.load_shapes.push_back(best.particle_loads[load_index(best, id)]);
  const long free_dofs =
      std::count(network.fixed.begin(), network.fixed.end(), false) * network.dimension;
  reduced_options.modes = static_cast<int>(std::min<long>(options.reduced_modes, free_dofs - 1));
  // 1 kHz, the haptic rate; the static response does not depend on it.
  const analysis::ReducedSpringModel reduced(network, 1e-3, reduced_options);
  row.reduced_basis = reduced.size();
  const std::vector<int> nodes = fitting::particle_of_node(setup.suite.problem, best.mesh);
  row.worst_fitted = worst_reduced_error(setup, best, reduced, nodes, best.fit, nullptr);
  row.worst_validation =
      worst_reduced_error(setup, best, reduced, nodes, best.holdout, &row.worst_case);
  StepTimingOptions timing;
  timing.samples = options.timing_samples;
  const StepTiming measured = measure_reduced_step(network, reduced, timing);
  row.measured_step_us = measured.median_us;
  row.measured_min_us = measured.min_us;
  row.measured_max_us = measured.max_us;
  // The runtime loads a reduced model file (export --format reduced) and steps it; MuJoCo and
  // SOFA have no subspace element and the MuJoCo callback runs networks only.
  row.engines = {"isospring runtime (reduced model)"};
  row.model = model_description(row);
  row.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return row;
}

}  // namespace isospring::workflows::frontier
