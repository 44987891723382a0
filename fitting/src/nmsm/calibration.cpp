// Calibration pipeline: reference, spring model, gamma sweep, fitted model, metrics. calibrate()
// lists the stages; the fits are in gamma_sweep.cpp, the metrics in calibration_metrics.cpp.
#include "isospring/fitting/calibration.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <stdexcept>

#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/constraints.hpp"
#include "isospring/analysis/sides.hpp"
#include "isospring/analysis/spring_mechanics.hpp"
#include "isospring/fitting/step_cost.hpp"
#include "isospring/nurbs/error.hpp"
#include "nmsm/calibration_stages.hpp"

namespace isospring::fitting {

namespace {

using detail::FitSetup;

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

bool contains(const std::vector<std::string>& list, const std::string& id) {
  return std::find(list.begin(), list.end(), id) != list.end();
}

// Stage: settings that name unknown load cases or contradict each other.
void check_settings(const analysis::Problem& problem, const CalibrationSettings& settings) {
  for (const auto& id : settings.fit_cases)
    if (std::none_of(problem.load_cases.begin(), problem.load_cases.end(),
                     [&](const auto& lc) { return lc.id == id; }))
      throw nurbs::InputError("calibration.fit_cases: no load case '" + id + "' in the case file");
  for (const auto& id : settings.holdout_cases)
    if (std::none_of(problem.load_cases.begin(), problem.load_cases.end(),
                     [&](const auto& lc) { return lc.id == id; }))
      throw nurbs::InputError("calibration.holdout_cases: no load case '" + id +
                              "' in the case file");

  if (settings.damping_alpha > 0.0 && settings.damping_ratio > 0.0)
    throw nurbs::InputError(
        "calibration: give damping_alpha or damping_ratio, not both (they define the same "
        "spring damping in two ways)");
}

// Stage: the IGA reference, solved or (settings.reference_displacements) given.
analysis::StaticResult reference_solution(const analysis::Problem& problem,
                                          const CalibrationSettings& settings,
                                          const analysis::DofMap& dofs) {
  if (settings.reference_displacements.empty()) return analysis::solve_static(problem);
  analysis::StaticResult reference;
  if (settings.reference_displacements.size() != problem.load_cases.size())
    throw std::invalid_argument("calibrate: one reference displacement per load case expected");
  for (size_t c = 0; c < problem.load_cases.size(); ++c) {
    if (settings.reference_displacements[c].size() != dofs.num_dofs())
      throw std::invalid_argument("calibrate: reference displacement of the wrong size");
    analysis::LoadCaseResult given;
    given.id = problem.load_cases[c].id;
    given.displacement = settings.reference_displacements[c];
    reference.load_cases.push_back(std::move(given));
  }
  return reference;
}

// Supports -> fixed particles (every component held) or single held components. The NMSM holds
// them at zero, so prescribed non-zero values cannot be represented.
void apply_supports(const analysis::Problem& problem, const analysis::DofMap& dofs,
                    const std::vector<int>& particle_of_node, SpringMesh& mesh,
                    std::vector<int>& extra_constrained) {
  const analysis::Constraints constraints = analysis::build_constraints(problem, dofs);
  const int dim = dofs.dofs_per_node();
  std::vector<int> particle_dofs;
  for (size_t c = 0; c < constraints.dofs.size(); ++c) {
    if (constraints.values[c] != 0.0)
      throw nurbs::InputError(
          "calibration: support values must be zero (the spring model holds "
          "supported control points in place); remove prescribed "
          "displacements from the calibrated case");
    const int node = constraints.dofs[c] / dim, component = constraints.dofs[c] % dim;
    particle_dofs.push_back(particle_of_node[node] * dim + component);
  }
  detail::hold_particle_dofs(std::move(particle_dofs), dim, mesh, extra_constrained);
}

Eigen::VectorXd particle_load(const Eigen::VectorXd& node_load,
                              const std::vector<int>& particle_of_node, int num_particles,
                              int dim) {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(num_particles) * dim);
  for (size_t a = 0; a < particle_of_node.size(); ++a)
    f.segment(particle_of_node[a] * dim, dim) +=
        node_load.segment(static_cast<Eigen::Index>(a) * dim, dim);
  return f;
}

// Stage: the spring mesh's masses and supports, the fitted and held-out cases and every case's
// load on the particles, into `setup` (its reference already solved).
void prepare_fit_data(const analysis::Problem& problem, const CalibrationSettings& settings,
                      SpringMesh& mesh, FitSetup& setup) {
  setup.particle_of_node = particle_of_node(problem, mesh);
  assign_masses(problem, mesh, settings.mass_model);

  DisplacementFitData& data = setup.data;
  apply_supports(problem, *setup.dofs, setup.particle_of_node, mesh, data.constrained_dofs);
  data.network = mesh.network;
  data.particle_of_node = setup.particle_of_node;
  for (size_t c = 0; c < problem.load_cases.size(); ++c) {
    const std::string& id = problem.load_cases[c].id;
    const bool holdout = contains(settings.holdout_cases, id);
    const bool fit = settings.fit_cases.empty() ? !holdout : contains(settings.fit_cases, id);
    if (fit)
      setup.fitted.push_back(static_cast<int>(c));
    else if (holdout)
      setup.held_out.push_back(static_cast<int>(c));
  }
  if (setup.fitted.empty())
    throw nurbs::InputError(
        "calibration: no load case left to fit; list some in "
        "calibration.fit_cases or remove them from holdout_cases");
  setup.loads.resize(problem.load_cases.size());
  for (size_t c = 0; c < problem.load_cases.size(); ++c)
    setup.loads[c] = particle_load(
        analysis::assemble_load(problem, *setup.dofs, problem.load_cases[c]),
        setup.particle_of_node, static_cast<int>(mesh.network.positions.size()), setup.dim);
  for (int c : setup.fitted) {
    data.loads.push_back(setup.loads[c]);
    data.references.push_back(setup.reference.load_cases[c].displacement);
  }
}

}  // namespace

namespace detail {

void hold_particle_dofs(std::vector<int> particle_dofs, int dim, SpringMesh& mesh,
                        std::vector<int>& extra_constrained) {
  std::vector<int> held(mesh.network.positions.size(), 0);
  std::sort(particle_dofs.begin(), particle_dofs.end());
  particle_dofs.erase(std::unique(particle_dofs.begin(), particle_dofs.end()), particle_dofs.end());
  for (int d : particle_dofs) ++held[d / dim];
  for (size_t q = 0; q < held.size(); ++q) mesh.network.fixed[q] = held[q] == dim;
  for (int d : particle_dofs)
    if (held[d / dim] != dim) extra_constrained.push_back(d);
}

void apply_fit(const CalibrationSettings& settings, CalibrationResult& result) {
  const DisplacementFitResult& fit = result.fit_result;
  detail::set_fitted(result.mesh.network, fit, result.grouping);
  result.parameters = result.grouping.num_groups();
  if (fit.groups_at_lower_bound > 0)
    result.warnings.push_back(
        std::to_string(fit.groups_at_lower_bound) + " of " + std::to_string(result.parameters) +
        " stiffness groups sit at the lower bound (1e-6 of the stiffest): the data would rather "
        "switch those springs off; they carry no load in the calibrated model");
  if (settings.damping_alpha > 0.0)
    analysis::assign_damping_alpha(result.mesh.network, settings.damping_alpha);
  if (settings.damping_ratio > 0.0)
    analysis::assign_damping_ratio(result.mesh.network, settings.damping_ratio);
}

}  // namespace detail

CalibrationResult calibrate(const analysis::Problem& problem, const CalibrationSettings& settings) {
  check_settings(problem, settings);

  CalibrationResult result;
  if (settings.progress && settings.reference_displacements.empty())
    settings.progress("IGA reference: solving the load cases");
  auto start = std::chrono::steady_clock::now();
  FitSetup setup(problem);
  setup.reference = reference_solution(problem, settings, *setup.dofs);
  result.reference_seconds = seconds_since(start);

  result.mesh = build_spring_mesh(problem, settings.mesh);
  check_step_budget(result.mesh.network, settings.max_step_us);
  prepare_fit_data(problem, settings, result.mesh, setup);
  for (size_t c = 0; c < problem.load_cases.size(); ++c)
    result.load_ids.push_back(problem.load_cases[c].id);
  result.particle_loads = setup.loads;

  const detail::FitBounds bounds = detail::fit_bounds(problem, settings, result.mesh, setup.dim);
  if (settings.matrix_approach && !result.mesh.network.volumes.empty())
    throw nurbs::InputError(
        "calibration: the matrix approach fits central springs only; turn off "
        "calibration.volume_terms / shear_terms or matrix_approach");

  start = std::chrono::steady_clock::now();
  detail::SweepOutcome sweep =
      detail::sweep_gammas(problem.material, settings, result.mesh, setup, bounds);
  result.fit_seconds = seconds_since(start);
  result.sweep = std::move(sweep.entries);
  result.fit_result = std::move(sweep.fit);
  result.grouping = std::move(sweep.grouping);
  result.gamma = sweep.gamma;
  detail::apply_fit(settings, result);

  // Faces inside the model (interfaces, seams, collapsed axes) are not its physical surface.
  const std::vector<std::array<bool, 6>> inner =
      analysis::inner_sides(problem.patches, *setup.dofs);
  detail::evaluate_cases(problem, settings, setup, inner, result.mesh.network, result.fit,
                         result.holdout);
  if (settings.matrix_approach)
    result.matrix = detail::compare_matrix_approach(problem, settings, setup, inner, result.mesh,
                                                    result.grouping);
  return result;
}

}  // namespace isospring::fitting
