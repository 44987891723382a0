// Calibration pipeline: reference, topology, loads, fit, metrics.
#include "isospring/fitting/calibration.hpp"

#include "isospring/fitting/prior_spring_fit.hpp"
#include "isospring/fitting/step_cost.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/constraints.hpp"
#include "isospring/analysis/dof_map.hpp"
#include "isospring/analysis/sides.hpp"
#include "isospring/analysis/spring_mechanics.hpp"
#include "isospring/analysis/spring_static.hpp"
#include "isospring/analysis/static_solver.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::fitting {

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

bool contains(const std::vector<std::string>& list, const std::string& id) {
  return std::find(list.begin(), list.end(), id) != list.end();
}

// Supports -> fixed particles (every component held) or single held components. The NMSM holds
// them at zero, so prescribed non-zero values cannot be represented.
void apply_supports(const analysis::Problem& problem, const analysis::DofMap& dofs,
                    const std::vector<int>& particle_of_node, SpringMesh& mesh,
                    std::vector<int>& extra_constrained) {
  const analysis::Constraints constraints = analysis::build_constraints(problem, dofs);
  const int dim = dofs.dofs_per_node();
  std::vector<int> held(mesh.network.positions.size(), 0);
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
  std::sort(particle_dofs.begin(), particle_dofs.end());
  particle_dofs.erase(std::unique(particle_dofs.begin(), particle_dofs.end()), particle_dofs.end());
  for (int d : particle_dofs) ++held[d / dim];
  for (size_t q = 0; q < held.size(); ++q) mesh.network.fixed[q] = held[q] == dim;
  for (int d : particle_dofs)
    if (held[d / dim] != dim) extra_constrained.push_back(d);
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

std::vector<Eigen::Vector3d> to_points(const Eigen::VectorXd& flat, int dim) {
  std::vector<Eigen::Vector3d> points(static_cast<size_t>(flat.size() / dim),
                                      Eigen::Vector3d::Zero());
  for (size_t a = 0; a < points.size(); ++a)
    for (int c = 0; c < dim; ++c) points[a][c] = flat[static_cast<Eigen::Index>(a) * dim + c];
  return points;
}

std::vector<std::vector<Eigen::Vector3d>> per_patch(
    const analysis::DofMap& dofs, const std::vector<Eigen::Vector3d>& node_values) {
  std::vector<std::vector<Eigen::Vector3d>> result(static_cast<size_t>(dofs.num_patches()));
  for (int p = 0; p < dofs.num_patches(); ++p)
    for (int node : dofs.patch_nodes(p)) result[p].push_back(node_values[node]);
  return result;
}

// The per-spring fit of prior_spring_fit.hpp in the form of a displacement fit's result.
DisplacementFitResult fit_with_prior(const DisplacementFitData& data,
                                     const std::vector<double>& prior,
                                     const CalibrationSettings& settings) {
  PriorSpringFitOptions options;
  options.prior = prior;
  options.weight = settings.prior_weight;
  options.max_iterations = settings.prior_max_iterations;
  const PriorSpringFitResult fit = fit_springs_with_prior(data, options);
  DisplacementFitResult result;
  result.spring_stiffness = fit.spring_stiffness;
  result.volume_modulus = fit.volume_modulus;
  result.group_stiffness = per_element_values(result);
  result.percent_e_rms = fit.percent_e_rms;
  result.percent_e_max = fit.percent_e_max;
  result.cost = fit.cost;
  result.iterations = fit.iterations;
  // L-BFGS stopping on the iteration limit still leaves a valid descent point: the penalty, not
  // the convergence, is what shapes this model.
  result.converged = true;
  result.message = fit.message;
  result.seconds = fit.seconds;
  return result;
}

// Why a fit cannot be the calibrated model, in calibrate()'s words; empty when it can.
std::string unusable_fit(const DisplacementFitResult& fit) {
  if (!fit.converged)
    return "calibration: the stiffness fit did not converge (" + fit.message +
           "); raise calibration.max_iterations or use fewer groups (larger gamma)";
  for (double k : fit.spring_stiffness)
    if (!(k > 0.0) || !std::isfinite(k))
      return "calibration: the fit produced a non-positive or non-finite spring";
  for (double kappa : fit.volume_modulus)
    if (!(kappa > 0.0) || !std::isfinite(kappa))
      return "calibration: the fit produced a non-positive or non-finite volume modulus";
  return "";
}

// The fitted stiffnesses and groups on the network's springs and volume terms.
void set_fitted(analysis::SpringNetwork& network, const DisplacementFitResult& fit,
                const Grouping& grouping) {
  for (size_t s = 0; s < network.springs.size(); ++s) {
    network.springs[s].stiffness = fit.spring_stiffness[s];
    network.springs[s].group = grouping.group_of_spring[s];
  }
  for (size_t v = 0; v < network.volumes.size(); ++v) {
    network.volumes[v].modulus = fit.volume_modulus[v];
    network.volumes[v].group = grouping.group_of_volume[v];
  }
}

bool same_grouping(const Grouping& a, const Grouping& b) {
  return a.group_of_spring == b.group_of_spring && a.group_of_volume == b.group_of_volume;
}

std::string gamma_text(double gamma) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", gamma);
  return text;
}

}  // namespace

CalibrationResult calibrate(const analysis::Problem& problem, const CalibrationSettings& settings) {
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

  CalibrationResult result;
  if (settings.progress && settings.reference_displacements.empty())
    settings.progress("IGA reference: solving the load cases");
  auto start = std::chrono::steady_clock::now();
  const analysis::DofMap dofs(problem);
  analysis::StaticResult reference;
  if (settings.reference_displacements.empty()) {
    reference = analysis::solve_static(problem);
  } else {
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
  }
  result.reference_seconds = seconds_since(start);

  const int dim = dofs.dofs_per_node();
  result.mesh = build_spring_mesh(problem, settings.mesh);
  SpringMesh& mesh = result.mesh;
  check_step_budget(mesh.network, settings.max_step_us);
  const std::vector<int> particle_of_node_map = particle_of_node(problem, mesh);
  assign_masses(problem, mesh, settings.mass_model);

  DisplacementFitData data;
  apply_supports(problem, dofs, particle_of_node_map, mesh, data.constrained_dofs);
  data.network = mesh.network;
  data.particle_of_node = particle_of_node_map;
  std::vector<int> fitted, held_out;
  for (size_t c = 0; c < problem.load_cases.size(); ++c) {
    const std::string& id = problem.load_cases[c].id;
    const bool holdout = contains(settings.holdout_cases, id);
    const bool fit = settings.fit_cases.empty() ? !holdout : contains(settings.fit_cases, id);
    if (fit)
      fitted.push_back(static_cast<int>(c));
    else if (holdout)
      held_out.push_back(static_cast<int>(c));
  }
  if (fitted.empty())
    throw nurbs::InputError(
        "calibration: no load case left to fit; list some in "
        "calibration.fit_cases or remove them from holdout_cases");
  std::vector<Eigen::VectorXd> loads(problem.load_cases.size());
  for (size_t c = 0; c < problem.load_cases.size(); ++c)
    loads[c] =
        particle_load(analysis::assemble_load(problem, dofs, problem.load_cases[c]),
                      particle_of_node_map, static_cast<int>(mesh.network.positions.size()), dim);
  for (size_t c = 0; c < problem.load_cases.size(); ++c)
    result.load_ids.push_back(problem.load_cases[c].id);
  result.particle_loads = loads;
  for (int c : fitted) {
    data.loads.push_back(loads[c]);
    data.references.push_back(reference.load_cases[c].displacement);
  }

  const std::vector<double> bounds =
      settings.upper_bounds ? stiffness_upper_bounds(problem, mesh) : std::vector<double>{};
  // Volume terms: 10 times the constrained modulus lambda + 2 mu (per unit thickness in 2D), far
  // above the kappa ~ lambda - mu a lattice needs; it only stops a runaway towards a rigid cell.
  const double nu = problem.material.poisson_ratio;
  const double volume_bound = 10.0 * problem.material.youngs_modulus * (1.0 - nu) /
                              ((1.0 + nu) * (1.0 - 2.0 * nu)) *
                              (dim == 2 ? problem.material.thickness : 1.0);
  if (settings.matrix_approach && !mesh.network.volumes.empty())
    throw nurbs::InputError(
        "calibration: the matrix approach fits central springs only; turn off "
        "calibration.volume_terms / shear_terms or matrix_approach");
  // The fit of one gamma whose rest-length groups are `groups`; `grouping` gets the fit's own
  // (one group per spring with per_spring).
  auto fit_with = [&](double gamma, const Grouping& groups, Grouping& grouping) {
    DisplacementFitOptions options;
    options.max_iterations = settings.max_iterations;
    options.min_stiffness_ratio = settings.min_stiffness_ratio;
    options.youngs_modulus = problem.material.youngs_modulus;
    if (settings.iteration) {
      char stage[64];
      std::snprintf(stage, sizeof stage, "fit (gamma %g)", gamma);
      options.on_iteration = [&settings, stage = std::string(stage)](int iteration, double cost) {
        settings.iteration(stage, iteration, cost);
      };
    } else if (settings.progress)
      options.on_iteration = [&settings, gamma](int iteration, double cost) {
        char line[160];
        std::snprintf(line, sizeof line, "fit (gamma %g): iteration %d, cost %.6g", gamma,
                      iteration, cost);
        settings.progress(line);
      };
    if (settings.per_spring) {
      // Start from the grouped optimum: the per-spring problem is large and underdetermined.
      if (settings.per_spring_start.empty()) {
        options.grouping = groups;
        options.initial = per_element_values(fit_displacements(data, options));
      } else if (settings.per_spring_start.size() ==
                 mesh.network.springs.size() + mesh.network.volumes.size()) {
        options.initial = settings.per_spring_start;
      } else {
        throw nurbs::InputError("calibration: per_spring_start has " +
                                std::to_string(settings.per_spring_start.size()) +
                                " stiffnesses for " + std::to_string(mesh.network.springs.size()) +
                                " springs and " + std::to_string(mesh.network.volumes.size()) +
                                " volume terms");
      }
      options.grouping = one_group_per_spring(mesh.network);
      if (settings.prior_weight > 0.0) {
        grouping = options.grouping;
        return fit_with_prior(data, options.initial, settings);
      }
      options.regularization = settings.regularization;
      options.regularization_groups = groups;
    } else {
      options.grouping = groups;
    }
    if (!bounds.empty()) {
      options.upper_bounds.assign(static_cast<size_t>(options.grouping.num_groups()), 0.0);
      for (size_t s = 0; s < bounds.size(); ++s) {
        double& b = options.upper_bounds[options.grouping.group_of_spring[s]];
        b = std::max(b, bounds[s]);
      }
      for (int g : options.grouping.group_of_volume) options.upper_bounds[g] = volume_bound;
    } else if (std::any_of(mesh.network.volumes.begin(), mesh.network.volumes.end(),
                           [](auto& t) { return t.kind == analysis::CellEnergy::kShear; })) {
      // Models with shear terms bound every cell modulus even without upper_bounds: a grouped
      // fit of a small model can otherwise trade springs for cells that run off towards rigid
      // (measured: mu ~ 1e12 Pa on a 3-element cantilever, which no time step can integrate).
      options.upper_bounds.assign(static_cast<size_t>(options.grouping.num_groups()), INFINITY);
      for (int g : options.grouping.group_of_volume) options.upper_bounds[g] = volume_bound;
    }
    grouping = options.grouping;
    return fit_displacements(data, options);
  };

  // Control-point displacements (node order, as points) of `network` under load case c.
  auto model_points = [&](const analysis::SpringNetwork& network, int c) {
    const Eigen::VectorXd u =
        analysis::solve_spring_linear(network, loads[c], data.constrained_dofs).displacement;
    Eigen::VectorXd node_u(dofs.num_dofs());
    for (int a = 0; a < dofs.num_nodes(); ++a)
      node_u.segment(a * dim, dim) = u.segment(particle_of_node_map[a] * dim, dim);
    return to_points(node_u, dim);
  };

  // The gamma sweep (SweepEntry): every gamma fitted unless its grouping repeats an earlier one,
  // a failing gamma recorded, the best usable one kept.
  start = std::chrono::steady_clock::now();
  std::vector<double> gammas = settings.gamma_sweep;
  if (gammas.empty()) gammas.push_back(settings.gamma);
  std::vector<Grouping> rest_groupings;  // per sweep entry
  double best_score = INFINITY;
  bool found = false;
  for (double gamma : gammas) {
    SweepEntry entry;
    entry.gamma = gamma;
    rest_groupings.push_back(group_by_rest_length(mesh.network, gamma));
    const Grouping& groups = rest_groupings.back();
    entry.groups = groups.num_groups();
    int same = -1;
    for (size_t e = 0; e + 1 < rest_groupings.size() && same < 0; ++e)
      if (result.sweep[e].reused_from < 0 && same_grouping(rest_groupings[e], groups))
        same = static_cast<int>(e);
    if (same >= 0) {
      entry = result.sweep[static_cast<size_t>(same)];
      entry.gamma = gamma;
      entry.reused_from = same;
      if (settings.progress)
        settings.progress("gamma " + gamma_text(gamma) + ": the grouping of gamma " +
                          gamma_text(result.sweep[static_cast<size_t>(same)].gamma) +
                          ", its fit reused");
      result.sweep.push_back(std::move(entry));
      continue;
    }
    try {
      Grouping grouping;
      DisplacementFitResult fit = fit_with(gamma, groups, grouping);
      entry.parameters = grouping.num_groups();
      double sum = 0.0;
      for (double e : fit.percent_e_rms) sum += e * e;
      entry.percent_e_rms = std::sqrt(sum / fit.percent_e_rms.size());
      for (double e : fit.percent_e_max) entry.percent_e_max = std::max(entry.percent_e_max, e);
      entry.group_stiffness = fit.group_stiffness;
      entry.spring_stiffness = fit.spring_stiffness;
      entry.volume_modulus = fit.volume_modulus;
      entry.failure = unusable_fit(fit);
      if (entry.failure.empty()) {
        analysis::SpringNetwork network = mesh.network;
        set_fitted(network, fit, grouping);
        double score = 0.0;
        for (int c : fitted) {
          entry.control.push_back(error_metrics(
              to_points(reference.load_cases[c].displacement, dim), model_points(network, c)));
          score += entry.control.back().percent_e_rms * entry.control.back().percent_e_rms;
        }
        score = std::sqrt(score / static_cast<double>(entry.control.size()));
        if (!std::isfinite(score)) {
          entry.control.clear();
          entry.failure = "calibration: the fitted model's error is not finite";
        } else if (!found || score < best_score) {
          found = true;
          best_score = score;
          result.fit_result = std::move(fit);
          result.grouping = std::move(grouping);
          result.gamma = gamma;
        }
      }
    } catch (const nurbs::InputError&) {
      throw;  // bad settings or data: no gamma can do better
    } catch (const std::runtime_error& e) {
      if (gammas.size() == 1) throw;
      entry.control.clear();
      entry.failure = e.what();
    }
    if (!entry.failure.empty() && settings.progress && gammas.size() > 1)
      settings.progress("gamma " + gamma_text(gamma) + " failed: " + entry.failure);
    result.sweep.push_back(std::move(entry));
  }
  result.fit_seconds = seconds_since(start);
  if (!found) {
    if (result.sweep.size() == 1) throw std::runtime_error(result.sweep[0].failure);
    std::string message = "calibration: every gamma of the sweep failed";
    for (const SweepEntry& entry : result.sweep)
      if (entry.reused_from < 0)
        message += "; gamma " + gamma_text(entry.gamma) + ": " + entry.failure;
    throw std::runtime_error(message);
  }
  const DisplacementFitResult& fit = result.fit_result;
  set_fitted(mesh.network, fit, result.grouping);
  result.parameters = result.grouping.num_groups();
  if (fit.groups_at_lower_bound > 0)
    result.warnings.push_back(
        std::to_string(fit.groups_at_lower_bound) + " of " + std::to_string(result.parameters) +
        " stiffness groups sit at the lower bound (1e-6 of the stiffest): the data would rather "
        "switch those springs off; they carry no load in the calibrated model");
  if (settings.damping_alpha > 0.0)
    analysis::assign_damping_alpha(mesh.network, settings.damping_alpha);
  if (settings.damping_ratio > 0.0)
    analysis::assign_damping_ratio(mesh.network, settings.damping_ratio);

  // Faces inside the model (interfaces, seams, collapsed axes) are not its physical surface.
  const std::vector<std::array<bool, 6>> inner = analysis::inner_sides(problem.patches, dofs);
  // Metrics per case of a network (fitted and held-out cases); throws when K is singular.
  auto evaluate = [&](const analysis::SpringNetwork& network, std::vector<CaseErrors>& fit_errors,
                      std::vector<CaseErrors>& holdout_errors) {
    for (size_t c = 0; c < problem.load_cases.size(); ++c) {
      const bool is_fit =
          std::find(fitted.begin(), fitted.end(), static_cast<int>(c)) != fitted.end();
      const bool is_holdout =
          std::find(held_out.begin(), held_out.end(), static_cast<int>(c)) != held_out.end();
      if (!is_fit && !is_holdout) continue;
      const auto ref_points = to_points(reference.load_cases[c].displacement, dim);
      const auto model = model_points(network, static_cast<int>(c));
      CaseErrors errors;
      errors.id = problem.load_cases[c].id;
      errors.control = error_metrics(ref_points, model);
      if (settings.field_metrics) {
        const auto ref_per_patch = per_patch(dofs, ref_points);
        const auto model_per_patch = per_patch(dofs, model);
        errors.field = field_error_metrics(problem.patches, ref_per_patch, model_per_patch,
                                           settings.field_samples);
        errors.surface = surface_error_metrics(problem.patches, ref_per_patch, model_per_patch,
                                               settings.field_samples, inner);
      }
      for (size_t a = 0; a < ref_points.size(); ++a)
        errors.node_error.push_back(model[a] - ref_points[a]);
      (is_fit ? fit_errors : holdout_errors).push_back(std::move(errors));
    }
  };
  evaluate(mesh.network, result.fit, result.holdout);

  if (settings.matrix_approach) {
    auto compare = [&](const std::string& method, const MatrixFitResult& fit) {
      MatrixComparison comparison;
      comparison.method = method;
      comparison.fit = fit;
      analysis::SpringNetwork network = mesh.network;
      for (size_t s = 0; s < network.springs.size(); ++s)
        network.springs[s].stiffness = fit.spring_stiffness[s];
      try {
        evaluate(network, comparison.fit_cases, comparison.holdout);
        comparison.solved = true;
      } catch (const std::runtime_error&) {
        comparison.fit_cases.clear();
        comparison.holdout.clear();
      }
      result.matrix.push_back(std::move(comparison));
    };
    compare("global", fit_stiffness_matrix(problem, mesh, result.grouping));
    bool linear = true;
    for (const auto& patch : problem.patches)
      for (int d = 0; d < patch.param_dim(); ++d) linear = linear && patch.degree(d) == 1;
    if (linear) compare("per_element", fit_stiffness_matrix_per_element(problem, mesh));
  }
  return result;
}

}  // namespace isospring::fitting
