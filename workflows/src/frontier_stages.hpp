#pragma once
// The stages of run_frontier (frontier.cpp lists them in order): one model kind calibrated and
// measured, the reduced model of the most accurate kind, and which engines accept a network.
// Private to the workflows module.
#include <optional>
#include <string>
#include <vector>

#include "isospring/fitting/calibration.hpp"
#include "isospring/fitting/thesis_experiments.hpp"
#include "isospring/workflows/frontier.hpp"

namespace isospring::workflows::frontier {

/// What a kind's calibration needs from its object: the suite with its training and validation
/// cases and the IGA reference solved once for all kinds.
struct ObjectSetup {
  fitting::ThesisObject object;
  fitting::ThesisSuite suite;
  std::vector<Eigen::VectorXd> reference;  // per load case of suite.problem
};

/// Stage: a network kind calibrated for generalisation (its freedoms cross-validated), then its
/// errors, measured step, estimate and engines. A failing calibration is a row with `failure`.
/// `calibration` receives the refitted model when there is one.
FrontierRow calibrate_kind(const ObjectSetup& setup, const FrontierKind& kind,
                           const FrontierOptions& options, const io::Progress& progress,
                           std::optional<fitting::CalibrationResult>& calibration);

/// Stage: the reduced model of `best` (a calibrated network of `best_row`'s kind) with the
/// lowest natural modes and the training loads' static responses as its basis; its static
/// errors on the fitted and validation cases and its measured step.
FrontierRow reduced_row(const ObjectSetup& setup, const fitting::CalibrationResult& best,
                        const FrontierRow& best_row, const FrontierOptions& options);

/// The engines whose export accepts `network`, tried with io's exporters: the runtime, MuJoCo
/// (springs as tendons), MuJoCo with the other terms in the runtime's passive-force callback,
/// SOFA.
std::vector<std::string> accepting_engines(const analysis::SpringNetwork& network);

/// The rows' Pareto flags: optimal on (measured step, worst held-out %e_rms) among the rows of
/// the object that did not fail (fitting::pareto_optimal).
void mark_pareto(FrontierObject& object);

/// "270 springs (reach 2) + 64 strain points, per spring w 1e-4 (gamma 0.2)".
std::string model_description(const FrontierRow& row);

}  // namespace isospring::workflows::frontier
