// run_calibrate: the calibration of `isospring calibrate` (see calibrate_command.hpp).
#include <algorithm>

#include "isospring/fitting/load_suite.hpp"
#include "isospring/io/report_case.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/workflows/calibrate_command.hpp"

#include "calibrate_large_deformation.hpp"

namespace isospring::workflows {
// The use cases read and write io's formats; io's names are used unqualified here.
using namespace isospring::io;

std::vector<std::string> calibrate_output_files(const std::vector<std::string>& load_case_ids) {
  std::vector<std::string> names{"report.json",           "report.md",  "model.json",
                                 "springs.vtp",           "result.vtm", "errors_histogram.png",
                                 "errors_vs_position.png"};
  for (const auto& id : load_case_ids) names.push_back(id + "_errors.csv");
  return names;
}

CalibrateCommandResult run_calibrate(Case c, const Progress& progress) {
  CalibrationRequest request = read_calibration_settings(c.calibration, c.file.string());
  if (c.nonlinear_material)
    return run_calibrate_large_deformation(std::move(c), std::move(request), progress);
  if (!request.amplitudes.empty())
    throw nurbs::InputError(c.file.filename().string() +
                            ": calibration.amplitudes: the amplitudes of a large-deformation "
                            "calibration need a finite-strain material.model (\"neo_hookean\" "
                            "or \"svk\"); remove them to calibrate linearly");
  fitting::CalibrationSettings& settings = request.settings;
  settings.matrix_approach = request.matrix_approach;
  if (!progress.quiet()) {
    settings.progress = [&progress](const std::string& line) { progress(line); };
    settings.iteration = [&progress](const std::string& stage, int iteration, double cost) {
      progress.update(stage, iteration, cost);
    };
  }

  // The load suite: its training cases are fitted beside the case's own, its
  // validation cases and the case's unfitted ones measured.
  if (request.load_suite) {
    const fitting::LoadSuite suite = fitting::generate_load_suite(c.problem, {});
    const bool fit_given = !settings.fit_cases.empty();
    for (const auto& lc : c.problem.load_cases)
      if (std::find(settings.fit_cases.begin(), settings.fit_cases.end(), lc.id) ==
              settings.fit_cases.end() &&
          std::find(settings.holdout_cases.begin(), settings.holdout_cases.end(), lc.id) ==
              settings.holdout_cases.end() &&
          !fit_given)
        settings.holdout_cases.push_back(lc.id);
    for (const auto& lc : suite.cases) c.problem.load_cases.push_back(lc);
    for (const auto& id : suite.training) settings.fit_cases.push_back(id);
    for (const auto& id : suite.validation) settings.holdout_cases.push_back(id);
    progress("load suite: " + std::to_string(suite.training.size()) + " training and " +
             std::to_string(suite.validation.size()) + " validation cases from the supports");
  }
  std::optional<fitting::GeneralisationResult> generalisation;
  if (request.generalisation) {
    settings.field_metrics = true;
    generalisation =
        fitting::calibrate_for_generalisation(c.problem, settings, *request.generalisation);
    const auto& chosen = generalisation->candidates[static_cast<size_t>(generalisation->chosen)];
    settings.gamma = chosen.gamma;
    settings.per_spring = chosen.prior_weight > 0.0;
    settings.prior_weight = chosen.prior_weight;
    settings.mesh.reach = chosen.reach;
    settings.mesh.volume_terms = chosen.volume_terms;
    settings.mesh.shear_terms = chosen.shear_terms;
    settings.mesh.strain_points = chosen.strain_points;
  }
  fitting::CalibrationResult computed = generalisation ? std::move(generalisation->calibration)
                                                       : fitting::calibrate(c.problem, settings);
  const fitting::CalibrationResult& result = computed;
  // The worst load case decides whether the model can be used: fitted and held out alike.
  double worst_fitted = 0.0, worst_holdout = 0.0;
  for (const auto& e : result.fit) worst_fitted = std::max(worst_fitted, e.control.percent_e_rms);
  for (const auto& e : result.holdout)
    worst_holdout = std::max(worst_holdout, e.control.percent_e_rms);
  const double worst = std::max(worst_fitted, worst_holdout);
  if (request.target_percent_e_rms > 0.0 && worst > request.target_percent_e_rms && !generalisation)
    computed.warnings.push_back("the worst %e_rms over fitted and held-out load cases (" +
                                format_number(worst, 3) + ") exceeds target_percent_e_rms " +
                                format_number(request.target_percent_e_rms, 3) +
                                ": the spring model does not reach the reference on every load");
  // Gammas of the sweep that failed were skipped (fitting::SweepEntry): say so, the kept gamma
  // may not be the one the case file's author expected.
  std::string failed_gammas;
  for (const auto& entry : result.sweep)
    if (!entry.failure.empty())
      failed_gammas += (failed_gammas.empty() ? "" : ", ") + format_number(entry.gamma);
  if (!failed_gammas.empty())
    computed.warnings.push_back("the fit of gamma " + failed_gammas +
                                " failed (report: sweep); kept gamma " +
                                format_number(result.gamma) + ", the best of the others");
  // Baseline beside the matrix approach: the acceleration objective on the same springs.
  std::optional<fitting::MatrixComparison> acceleration;
  if (request.acceleration_objective && !result.mesh.network.volumes.empty())
    progress(
        "acceleration objective skipped: it fits central springs only and the calibrated "
        "model has volume or shear terms");
  else if (request.acceleration_objective) {
    progress("acceleration objective [S15 4.1-4.5] on the same springs (baseline)");
    acceleration = fitting::acceleration_baseline(c.problem, settings, result);
  }
  for (const auto& warning : result.mesh.warnings) progress.warn(warning);
  for (const auto& warning : result.warnings) progress.warn(warning);

  CalibrateCommandResult r;
  r.input = c.file;
  r.case_name = c.name;
  r.case_summary = case_summary(c, c.problem);  // with the load suite, as the report has it
  // The callbacks refer to `progress`, which the result outlives.
  settings.progress = nullptr;
  settings.iteration = nullptr;
  r.request = std::move(request);
  r.generalisation = std::move(generalisation);
  r.calibration = std::move(computed);
  r.acceleration = std::move(acceleration);
  r.worst_fitted = worst_fitted;
  r.worst_holdout = worst_holdout;
  r.worst = worst;
  r.problem = std::move(c.problem);
  return r;
}

}  // namespace isospring::workflows
