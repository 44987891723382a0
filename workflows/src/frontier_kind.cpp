// One model kind of the frontier: calibrated for generalisation, measured, its engines
// (frontier_stages.hpp).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "frontier_stages.hpp"
#include "isospring/fitting/generalising_calibration.hpp"
#include "isospring/fitting/step_cost.hpp"
#include "isospring/io/export_mjcf.hpp"
#include "isospring/io/export_sofa.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/workflows/runtime_step_timing.hpp"

namespace isospring::workflows::frontier {

namespace {

// The freedoms cross-validation chooses within a kind, fewer than the generalisation table of
// `thesis` offers (six kinds per object instead of two or three). Membranes (110 springs; 270
// with reach 2): both reaches, three gammas and per spring with w = 1e-4 (the table's choice for
// all three), 1500 L-BFGS iterations. Solids (1600 to 2000 springs, 19 to 23 training cases,
// seconds to minutes per fit, times 3 folds): grouped only, gamma 0.5 or 0.2 (around [S15]'s
// and the table's choices); no per-spring candidates, which cost the table minutes per kind, so
// a solid's point can sit above that table's number for the same kind.
fitting::GeneralisationOptions kind_candidates(const fitting::ThesisObject& object,
                                               const FrontierKind& kind, bool quick,
                                               int& prior_iterations) {
  fitting::GeneralisationOptions options;
  const bool solid = object.problem.formulation == analysis::Formulation::kSolid;
  if (solid) {
    options.gammas = quick ? std::vector<double>{0.5} : std::vector<double>{0.5, 0.2};
    options.prior_weights = {};
    options.reaches = {1};
  } else {
    options.gammas = quick ? std::vector<double>{0.5, 0.01} : std::vector<double>{0.5, 0.2, 0.01};
    options.prior_weights = {1e-4};
    options.reaches = quick ? std::vector<int>{1} : std::vector<int>{1, 2};
    prior_iterations = quick ? 300 : 1500;
  }
  options.volume_terms = {kind.volume_terms};
  options.shear_terms = {kind.shear_terms};
  options.strain_points = {kind.strain_points};
  options.folds = 3;
  return options;
}

size_t count_terms(const analysis::SpringNetwork& network, analysis::CellEnergy kind, bool points) {
  return static_cast<size_t>(
      std::count_if(network.volumes.begin(), network.volumes.end(),
                    [&](const auto& t) { return t.kind == kind && t.points.empty() != points; }));
}

std::string short_number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", x);
  return text;
}

}  // namespace

std::vector<std::string> accepting_engines(const analysis::SpringNetwork& network) {
  // The runtime loads every network io writes (the step was measured through it).
  std::vector<std::string> engines = {"isospring runtime"};
  auto accepts = [](auto&& export_it) {
    try {
      export_it();
      return true;
    } catch (const nurbs::InputError&) {
      return false;  // the exporter refuses the model (e.g. terms the engine has no element for)
    }
  };
  const Eigen::Vector3d gravity =
      io::engine_gravity(network, Eigen::Vector3d::Zero(), std::nullopt);
  io::MjcfOptions mjcf;
  mjcf.gravity = gravity;
  if (accepts([&] { (void)io::mjcf_document(network, mjcf); })) {
    engines.push_back("MuJoCo (tendons)");
  } else {
    mjcf.runtime_model = "model.isospring.json";
    if (accepts([&] { (void)io::mjcf_document(network, mjcf); }))
      engines.push_back("MuJoCo (tendons + runtime callback)");
  }
  io::SofaOptions sofa;
  sofa.gravity = gravity;
  if (accepts([&] { (void)io::sofa_scene(network, sofa); })) engines.push_back("SOFA");
  return engines;
}

std::string model_description(const FrontierRow& row) {
  if (row.kind.reduced)
    return "reduced, r = " + std::to_string(row.reduced_basis) + ", of the " + row.reduced_of +
           " model";
  std::string text =
      std::to_string(row.springs) + " springs (reach " + std::to_string(row.reach) + ")";
  if (row.cell_volume_terms > 0)
    text += " + " + std::to_string(row.cell_volume_terms) + " volume terms";
  if (row.cell_shear_terms > 0)
    text += " + " + std::to_string(row.cell_shear_terms) + " shear terms";
  if (row.strain_point_terms > 0)
    text += " + " + std::to_string(row.strain_point_terms) + " strain points";
  text += row.prior_weight > 0.0 ? ", per spring, w " + short_number(row.prior_weight) +
                                       " (gamma " + short_number(row.gamma) + ")"
                                 : ", " + std::to_string(row.parameters) + " groups (gamma " +
                                       short_number(row.gamma) + ")";
  return text;
}

FrontierRow calibrate_kind(const ObjectSetup& setup, const FrontierKind& kind,
                           const FrontierOptions& options, const io::Progress& progress,
                           std::optional<fitting::CalibrationResult>& calibration) {
  const auto start = std::chrono::steady_clock::now();
  FrontierRow row;
  row.kind = kind;
  fitting::CalibrationSettings settings;
  settings.fit_cases = setup.suite.training;
  settings.holdout_cases = setup.suite.validation;
  settings.reference_displacements = setup.reference;
  settings.max_iterations = 3000;
  settings.field_metrics = false;
  const fitting::GeneralisationOptions candidates =
      kind_candidates(setup.object, kind, options.quick, settings.prior_max_iterations);
  try {
    fitting::GeneralisationResult g =
        fitting::calibrate_for_generalisation(setup.suite.problem, settings, candidates);
    const fitting::CandidateScore& chosen = g.candidates[static_cast<size_t>(g.chosen)];
    const fitting::CalibrationResult& r = g.calibration;
    const analysis::SpringNetwork& network = r.mesh.network;
    row.reach = chosen.reach;
    row.gamma = chosen.gamma;
    row.prior_weight = chosen.prior_weight;
    row.parameters = r.parameters;
    row.springs = network.springs.size();
    row.cell_volume_terms = count_terms(network, analysis::CellEnergy::kVolume, false);
    row.cell_shear_terms = count_terms(network, analysis::CellEnergy::kShear, false);
    row.strain_point_terms = count_terms(network, analysis::CellEnergy::kShear, true);
    row.cross_validation_worst = chosen.worst;
    row.worst_fitted = g.worst_fitted;
    row.worst_validation = g.worst_validation;
    for (const fitting::CaseErrors& e : r.holdout)
      if (e.control.percent_e_rms == g.worst_validation) row.worst_case = e.id;
    StepTimingOptions timing;
    timing.samples = options.timing_samples;
    const StepTiming measured = measure_network_step(network, timing);
    row.measured_step_us = measured.median_us;
    row.measured_min_us = measured.min_us;
    row.measured_max_us = measured.max_us;
    row.estimated_step_us = fitting::estimated_step_us(network);
    row.engines = accepting_engines(network);
    row.model = model_description(row);
    calibration = std::move(g.calibration);
  } catch (const std::runtime_error& e) {
    row.failure = e.what();
    row.worst_validation = row.worst_fitted = row.cross_validation_worst = NAN;
    row.measured_step_us = row.estimated_step_us = NAN;
  }
  row.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  progress(setup.object.name + ": " + kind.name + ": " +
           (row.failure.empty()
                ? "worst held-out %e_rms " + io::format_number(row.worst_validation, 3) +
                      ", step " + io::format_number(row.measured_step_us, 3) + " us measured (" +
                      io::format_number(row.estimated_step_us, 3) + " us estimated), " +
                      io::format_number(row.seconds, 3) + " s"
                : "failed (" + row.failure + ")"));
  return row;
}

}  // namespace isospring::workflows::frontier
