// calibrate()'s fits: the bounds they share, the fit of one gamma, and the gamma sweep
// (Algorithm 5.1) that keeps the best usable one.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "isospring/fitting/prior_spring_fit.hpp"
#include "isospring/nurbs/error.hpp"
#include "nmsm/calibration_stages.hpp"

namespace isospring::fitting::detail {

namespace {

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

bool same_grouping(const Grouping& a, const Grouping& b) {
  return a.group_of_spring == b.group_of_spring && a.group_of_volume == b.group_of_volume;
}

std::string gamma_text(double gamma) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", gamma);
  return text;
}

// What every gamma's fit reads: sweep_gammas' arguments.
struct SweepInputs {
  const analysis::Material& material;
  const CalibrationSettings& settings;
  const SpringMesh& mesh;
  const FitSetup& setup;
  const FitBounds& bounds;
};

// The fit's iterations as settings.iteration calls (a terminal's updating line) or, without
// one, as settings.progress lines; none when neither is set.
void report_iterations(const CalibrationSettings& settings, double gamma,
                       DisplacementFitOptions& options) {
  if (settings.iteration) {
    char stage[64];
    std::snprintf(stage, sizeof stage, "fit (gamma %g)", gamma);
    options.on_iteration = [&settings, stage = std::string(stage)](int iteration, double cost) {
      settings.iteration(stage, iteration, cost);
    };
  } else if (settings.progress)
    options.on_iteration = [&settings, gamma](int iteration, double cost) {
      char line[160];
      std::snprintf(line, sizeof line, "fit (gamma %g): iteration %d, cost %.6g", gamma, iteration,
                    cost);
      settings.progress(line);
    };
}

// The upper bound of every fitted group: the largest of its springs' bounds, `bounds.volume`
// for volume terms. Models with shear terms bound every cell modulus even without
// upper_bounds: a grouped fit of a small model can otherwise trade springs for cells that run
// off towards rigid (measured: mu ~ 1e12 Pa on a 3-element cantilever, which no time step can
// integrate).
void set_upper_bounds(const SpringMesh& mesh, const FitBounds& bounds,
                      DisplacementFitOptions& options) {
  if (!bounds.spring.empty()) {
    options.upper_bounds.assign(static_cast<size_t>(options.grouping.num_groups()), 0.0);
    for (size_t s = 0; s < bounds.spring.size(); ++s) {
      double& b = options.upper_bounds[options.grouping.group_of_spring[s]];
      b = std::max(b, bounds.spring[s]);
    }
    for (int g : options.grouping.group_of_volume) options.upper_bounds[g] = bounds.volume;
  } else if (std::any_of(mesh.network.volumes.begin(), mesh.network.volumes.end(),
                         [](auto& t) { return t.kind == analysis::CellEnergy::kShear; })) {
    options.upper_bounds.assign(static_cast<size_t>(options.grouping.num_groups()), INFINITY);
    for (int g : options.grouping.group_of_volume) options.upper_bounds[g] = bounds.volume;
  }
}

// The fit of one gamma whose rest-length groups are `groups`; `grouping` gets the fit's own
// (one group per spring with per_spring).
DisplacementFitResult fit_gamma(const SweepInputs& in, double gamma, const Grouping& groups,
                                Grouping& grouping) {
  const CalibrationSettings& settings = in.settings;
  const SpringMesh& mesh = in.mesh;
  DisplacementFitOptions options;
  options.max_iterations = settings.max_iterations;
  options.min_stiffness_ratio = settings.min_stiffness_ratio;
  options.youngs_modulus = in.material.youngs_modulus;
  report_iterations(settings, gamma, options);
  if (settings.per_spring) {
    // Start from the grouped optimum: the per-spring problem is large and underdetermined.
    if (settings.per_spring_start.empty()) {
      options.grouping = groups;
      options.initial = per_element_values(fit_displacements(in.setup.data, options));
    } else if (settings.per_spring_start.size() ==
               mesh.network.springs.size() + mesh.network.volumes.size()) {
      options.initial = settings.per_spring_start;
    } else {
      throw nurbs::InputError(
          "calibration: per_spring_start has " + std::to_string(settings.per_spring_start.size()) +
          " stiffnesses for " + std::to_string(mesh.network.springs.size()) + " springs and " +
          std::to_string(mesh.network.volumes.size()) + " volume terms");
    }
    options.grouping = one_group_per_spring(mesh.network);
    if (settings.prior_weight > 0.0) {
      grouping = options.grouping;
      return fit_with_prior(in.setup.data, options.initial, settings);
    }
    options.regularization = settings.regularization;
    options.regularization_groups = groups;
  } else {
    options.grouping = groups;
  }
  set_upper_bounds(mesh, in.bounds, options);
  grouping = options.grouping;
  return fit_displacements(in.setup.data, options);
}

// Fits `gamma` into `entry` and scores the usable fit by the control-point error of a fresh
// linear solve per fitted case; the best so far moves into `outcome`. Throws what the fit or
// the solve throws (the caller records a std::runtime_error as the entry's failure).
void fit_and_score(const SweepInputs& in, const Grouping& groups, SweepEntry& entry,
                   SweepOutcome& outcome, double& best_score, bool& found) {
  const FitSetup& setup = in.setup;
  Grouping grouping;
  DisplacementFitResult fit = fit_gamma(in, entry.gamma, groups, grouping);
  entry.parameters = grouping.num_groups();
  double sum = 0.0;
  for (double e : fit.percent_e_rms) sum += e * e;
  entry.percent_e_rms = std::sqrt(sum / fit.percent_e_rms.size());
  for (double e : fit.percent_e_max) entry.percent_e_max = std::max(entry.percent_e_max, e);
  entry.group_stiffness = fit.group_stiffness;
  entry.spring_stiffness = fit.spring_stiffness;
  entry.volume_modulus = fit.volume_modulus;
  entry.failure = unusable_fit(fit);
  if (!entry.failure.empty()) return;
  analysis::SpringNetwork network = in.mesh.network;
  set_fitted(network, fit, grouping);
  double score = 0.0;
  const analysis::SpringLinearSolver solver = network_solver(setup, network);
  for (int c : setup.fitted) {
    entry.control.push_back(
        error_metrics(to_points(setup.reference.load_cases[c].displacement, setup.dim),
                      model_points(setup, solver, c)));
    score += entry.control.back().percent_e_rms * entry.control.back().percent_e_rms;
  }
  score = std::sqrt(score / static_cast<double>(entry.control.size()));
  if (!std::isfinite(score)) {
    entry.control.clear();
    entry.failure = "calibration: the fitted model's error is not finite";
  } else if (!found || score < best_score) {
    found = true;
    best_score = score;
    outcome.fit = std::move(fit);
    outcome.grouping = std::move(grouping);
    outcome.gamma = entry.gamma;
  }
}

// Index of the earlier fitted (not reused) entry whose rest-length grouping equals the last
// one of `rest_groupings`; -1 when there is none.
int earlier_same_grouping(const std::vector<Grouping>& rest_groupings,
                          const std::vector<SweepEntry>& entries) {
  const Grouping& groups = rest_groupings.back();
  for (size_t e = 0; e + 1 < rest_groupings.size(); ++e)
    if (entries[e].reused_from < 0 && same_grouping(rest_groupings[e], groups))
      return static_cast<int>(e);
  return -1;
}

// Why no gamma could be kept: the one gamma's message, or every fitted gamma's.
std::runtime_error sweep_failure(const std::vector<SweepEntry>& entries) {
  if (entries.size() == 1) return std::runtime_error(entries[0].failure);
  std::string message = "calibration: every gamma of the sweep failed";
  for (const SweepEntry& entry : entries)
    if (entry.reused_from < 0)
      message += "; gamma " + gamma_text(entry.gamma) + ": " + entry.failure;
  return std::runtime_error(message);
}

}  // namespace

FitBounds fit_bounds(const analysis::Problem& problem, const CalibrationSettings& settings,
                     const SpringMesh& mesh, int dim) {
  FitBounds bounds;
  if (settings.upper_bounds) bounds.spring = stiffness_upper_bounds(problem, mesh);
  bounds.volume = volume_term_bound(problem.material, dim);
  return bounds;
}

double volume_term_bound(const analysis::Material& material, int dim) {
  // 10 times the constrained modulus lambda + 2 mu (per unit thickness in 2D), far above the
  // kappa ~ lambda - mu a lattice needs; it only stops a runaway towards a rigid cell.
  const double nu = material.poisson_ratio;
  return 10.0 * material.youngs_modulus * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu)) *
         (dim == 2 ? material.thickness : 1.0);
}

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

SweepOutcome sweep_gammas(const analysis::Material& material, const CalibrationSettings& settings,
                          const SpringMesh& mesh, const FitSetup& setup, const FitBounds& bounds) {
  std::vector<double> gammas = settings.gamma_sweep;
  if (gammas.empty()) gammas.push_back(settings.gamma);
  const SweepInputs inputs{material, settings, mesh, setup, bounds};
  SweepOutcome outcome;
  std::vector<Grouping> rest_groupings;  // per sweep entry
  double best_score = INFINITY;
  bool found = false;
  for (double gamma : gammas) {
    SweepEntry entry;
    entry.gamma = gamma;
    rest_groupings.push_back(group_by_rest_length(mesh.network, gamma));
    const Grouping& groups = rest_groupings.back();
    entry.groups = groups.num_groups();
    // The same data and grouping give the same fit: copy it instead of fitting again.
    if (const int same = earlier_same_grouping(rest_groupings, outcome.entries); same >= 0) {
      const SweepEntry& original = outcome.entries[static_cast<size_t>(same)];
      entry = original;
      entry.gamma = gamma;
      entry.reused_from = same;
      if (settings.progress)
        settings.progress("gamma " + gamma_text(gamma) + ": the grouping of gamma " +
                          gamma_text(original.gamma) + ", its fit reused");
      outcome.entries.push_back(std::move(entry));
      continue;
    }
    try {
      fit_and_score(inputs, groups, entry, outcome, best_score, found);
    } catch (const nurbs::InputError&) {
      throw;  // bad settings or data: no gamma can do better
    } catch (const std::runtime_error& e) {
      if (gammas.size() == 1) throw;
      entry.control.clear();
      entry.failure = e.what();
    }
    if (!entry.failure.empty() && settings.progress && gammas.size() > 1)
      settings.progress("gamma " + gamma_text(gamma) + " failed: " + entry.failure);
    outcome.entries.push_back(std::move(entry));
  }
  if (!found) throw sweep_failure(outcome.entries);
  return outcome;
}

}  // namespace isospring::fitting::detail
