// calibrate_immersed's last stage: the calibrated network's errors against the immersed
// reference, on the control points (as calibrate()) and as spline fields over the part.
#include <algorithm>
#include <cmath>

#include "isospring/analysis/immersed_particles.hpp"
#include "isospring/nurbs/error.hpp"
#include "nmsm/immersed_calibration_stages.hpp"

namespace isospring::fitting::detail {

namespace {

// Weighted %e_rms (100 sqrt(sum w |e|^2 / sum w) / o_max): a quadrature's points crowd in cut
// cells and near edges, so an unweighted mean would count those regions many times over.
ErrorMetrics weighted_metrics(const std::vector<Eigen::Vector3d>& reference,
                              const std::vector<Eigen::Vector3d>& model,
                              const std::vector<double>& weights) {
  ErrorMetrics m;
  double sum = 0.0, total = 0.0, worst = 0.0;
  for (size_t q = 0; q < reference.size(); ++q) {
    const double e = (model[q] - reference[q]).norm();
    sum += weights[q] * e * e;
    total += weights[q];
    worst = std::max(worst, e);
    m.o_max = std::max(m.o_max, reference[q].norm());
  }
  m.points = static_cast<int>(reference.size());
  if (!(m.o_max > 0.0) || !(total > 0.0))
    throw nurbs::InputError("calibration: the reference displacement is zero on the part");
  m.percent_e_rms = 100.0 * std::sqrt(sum / total) / m.o_max;
  m.percent_e_max = 100.0 * worst / m.o_max;
  return m;
}

// Per background control point: the node values (flat, node * dim + c) or zero where inactive.
std::vector<Eigen::Vector3d> on_background(const ImmersedFit& fit,
                                           const std::vector<Eigen::Vector3d>& node_values) {
  std::vector<Eigen::Vector3d> values(fit.node_of_control_point.size(), Eigen::Vector3d::Zero());
  for (size_t cp = 0; cp < values.size(); ++cp)
    if (const int node = fit.node_of_control_point[cp]; node >= 0)
      values[cp] = node_values[static_cast<size_t>(node)];
  return values;
}

struct QuadraturePoints {
  std::vector<Eigen::Vector3d> points;
  std::vector<double> weights;
};

QuadraturePoints volume_points(const geometry::ImmersedDomain& domain) {
  QuadraturePoints q;
  for (const geometry::ImmersedCell& cell : domain.cells) {
    q.points.insert(q.points.end(), cell.points.begin(), cell.points.end());
    q.weights.insert(q.weights.end(), cell.weights.begin(), cell.weights.end());
  }
  return q;
}

QuadraturePoints surface_points(const geometry::ImmersedDomain& domain) {
  QuadraturePoints q;
  for (const geometry::BoundaryPoint& b : domain.boundary) {
    q.points.push_back(b.point);
    q.weights.push_back(b.weight);
  }
  return q;
}

}  // namespace

void evaluate_immersed_cases(const geometry::ImmersedDomain& domain,
                             const std::vector<ImmersedCalibrationCase>& cases,
                             const CalibrationSettings& settings, const ImmersedFit& fit,
                             ImmersedCalibrationResult& result) {
  const FitSetup& setup = fit.setup;
  const analysis::SpringNetwork& network = result.calibration.mesh.network;
  QuadraturePoints volume, surface;
  if (settings.field_metrics) {
    volume = volume_points(domain);
    surface = surface_points(domain);
  }
  result.model_control_displacements.assign(cases.size(), {});
  const analysis::SpringLinearSolver solver = network_solver(setup, network);
  for (size_t c = 0; c < cases.size(); ++c) {
    const int index = static_cast<int>(c);
    const bool is_fit = std::count(setup.fitted.begin(), setup.fitted.end(), index) > 0;
    const bool is_holdout = std::count(setup.held_out.begin(), setup.held_out.end(), index) > 0;
    if (!is_fit && !is_holdout) continue;
    const auto reference = to_points(setup.reference.load_cases[c].displacement, setup.dim);
    const auto model = model_points(setup, solver, index);
    CaseErrors errors;
    errors.id = cases[c].id;
    errors.control = error_metrics(reference, model);
    for (size_t a = 0; a < reference.size(); ++a)
      errors.node_error.push_back(model[a] - reference[a]);
    result.model_control_displacements[c] = on_background(fit, model);
    if (settings.field_metrics) {
      const auto& ref_values = result.reference[c].control_displacements;
      const auto& model_values = result.model_control_displacements[c];
      for (auto [where, metrics] : {std::pair{&volume, &errors.field}, {&surface, &errors.surface}})
        *metrics = weighted_metrics(
            analysis::evaluate_immersed_field(domain, ref_values, where->points),
            analysis::evaluate_immersed_field(domain, model_values, where->points), where->weights);
    }
    (is_fit ? result.calibration.fit : result.calibration.holdout).push_back(std::move(errors));
  }
}

}  // namespace isospring::fitting::detail
