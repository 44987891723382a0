#pragma once
// Cost against accuracy, per object: for each [S15] object (fitting/thesis_experiments.hpp) and
// each model kind the calibration offers, the model calibrated for generalisation within that
// kind (fitting/generalising_calibration.hpp: 3-fold cross-validation over the load suite's
// training cases chooses the other freedoms, reach, gamma, per-spring weight, and the choice is
// refitted on every training case), its worst held-out %e_rms (validation cases never fitted),
// its cost per engine step MEASURED with the runtime on that exact model
// (runtime_step_timing.hpp) beside fitting/step_cost.hpp's estimate, which engines accept it
// (io's exporters, tried), and the Pareto-optimal kinds (fitting/pareto.hpp). `isospring thesis
// --frontier` runs it.
//
// The kinds: springs only; + a volume (2D: area) term per net cell; + volume and shear terms per
// net cell; springs + strain points at 1, 2 and 3 Gauss points per direction of every knot span
// (each point carries its own volume and shear modulus, which makes cell terms redundant beside
// them); and the reduced model (analysis/spring_reduced_model.hpp) of the most accurate of
// those: its basis is the lowest natural modes plus the static responses of the TRAINING loads
// only, so its static held-out error is the full model's plus the projection's, measured like
// the others (u = Phi Lambda^-1 Phi^T f against the IGA reference on the control points).
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "isospring/io/report.hpp"

namespace isospring::workflows {

/// A model kind of the frontier.
struct FrontierKind {
  std::string name;  // "springs", "springs + volume terms", ..., "reduced"
  bool volume_terms = false, shear_terms = false;
  int strain_points = 0;  // per direction per knot span
  bool reduced = false;   // the reduced model of the most accurate other kind
};

/// Every kind, cheapest first (the reduced model last: it needs the others).
std::vector<FrontierKind> frontier_kinds();

struct FrontierRow {
  FrontierKind kind;
  /// Empty: calibrated and measured. Otherwise why not (the cells below are NaN / empty).
  std::string failure;
  // The model chosen within the kind.
  int reach = 1;
  double gamma = 0.0, prior_weight = 0.0;  // prior_weight 0: grouped
  int parameters = 0;
  size_t springs = 0, cell_volume_terms = 0, cell_shear_terms = 0, strain_point_terms = 0;
  int reduced_basis = 0;   // the reduced model's basis size (0 for a network)
  std::string reduced_of;  // the reduced model: the kind whose model it reduces
  std::string model;       // the chosen model in words (frontier_stages.hpp model_description)
  double cross_validation_worst = 0.0;  // the score that chose it (NaN for the reduced model)
  double worst_validation = 0.0;        // %e_rms, control points, validation cases
  double worst_fitted = 0.0;            // %e_rms over the training cases
  std::string worst_case;               // the validation case of worst_validation
  double measured_step_us = 0.0;        // runtime, CPU microseconds per step (median)
  double measured_min_us = 0.0, measured_max_us = 0.0;
  double estimated_step_us = 0.0;    // step_cost.hpp (forces only; NaN for the reduced model)
  std::vector<std::string> engines;  // what accepts the model
  bool pareto = false;               // on the object's frontier (measured cost, worst held-out)
  double seconds = 0.0;              // wall time of the kind's calibration
};

struct FrontierObject {
  std::string name;
  size_t training_cases = 0, validation_cases = 0;
  double published_e_rms = 0.0;  // [S15] Table 5.3, fitted case
  std::vector<FrontierRow> rows;
  double seconds = 0.0;
  bool complete = false;  // false while (or when a run stopped before) its last kind ran
};

struct FrontierResult {
  std::vector<FrontierObject> objects;
  std::string machine;  // CPU, cores, load average at the start and the end
};

struct FrontierOptions {
  /// Objects to run (empty: all six, in the order square, circle, ellipse, cube, torus,
  /// coupled_spheroid, cheapest first).
  std::vector<std::string> objects;
  /// Kinds to run (empty: frontier_kinds()); a reduced kind needs at least one other.
  std::vector<FrontierKind> kinds;
  /// Fewer candidates within each kind (tests, smoke runs).
  bool quick = false;
  int reduced_modes = 32;   // lowest natural modes of the reduced model's basis
  int timing_samples = 21;  // StepTimingOptions::samples
  /// Called after each kind of each object with the result so far (a long run writes its
  /// outputs as it goes: stopped early, it keeps the kinds that finished).
  std::function<void(const FrontierResult&)> on_object;
};

/// Runs the frontier. Throws nurbs::InputError for an unknown object or a kind list without a
/// network kind; a kind whose calibration fails is a row with its failure, not an exception.
FrontierResult run_frontier(const FrontierOptions& options, const io::Progress& progress);

/// report.json's content.
nlohmann::json frontier_report_json(const FrontierResult& result);
/// report.md's content; `figure` (a file name next to it, empty: none) is linked.
io::MarkdownReport frontier_report_markdown(const FrontierResult& result,
                                            const std::string& figure);
/// Writes report.json, report.md and frontier.png (when gnuplot is available) into `out_dir`
/// (created), each atomically.
void write_frontier_outputs(const std::filesystem::path& out_dir, const FrontierResult& result);

/// A result back from report.json contents (frontier_report_json's), e.g. to combine runs of
/// single objects made apart (run_frontier's objects are independent). Throws
/// nurbs::InputError naming `source` and the key when the document is not a frontier report.
FrontierResult frontier_result_from_json(const nlohmann::json& report, const std::string& source);

/// frontier_result_from_json of a report.json file.
FrontierResult read_frontier_report(const std::filesystem::path& path);

/// Several results as one: their objects in order (an object named twice: the later run's),
/// their machine lines joined.
FrontierResult combine_frontier_results(const std::vector<FrontierResult>& results);

/// The files write_frontier_outputs writes.
std::vector<std::string> frontier_output_files();

}  // namespace isospring::workflows
