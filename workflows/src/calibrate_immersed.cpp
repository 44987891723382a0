// run_calibrate_immersed (see calibrate_immersed.hpp); its files are in
// calibrate_immersed_outputs.cpp.
#include "isospring/workflows/calibrate_immersed.hpp"

#include <algorithm>

#include "isospring/nurbs/error.hpp"

namespace isospring::workflows {
using namespace isospring::io;
namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// The "calibration" object of the case, with the settings that have no immersed form refused
// and the two baselines that default to on switched off.
CalibrationRequest immersed_request(const ImmersedCase& c) {
  const nlohmann::json calibration =
      c.raw.contains("calibration") ? c.raw.at("calibration") : nlohmann::json();
  CalibrationRequest request = read_calibration_settings(calibration, c.file.string());
  const std::string where = c.file.filename().string() + ": calibration.";
  const std::string body_fitted = " has no immersed form: it builds on a body-fitted model's ";
  if (request.generalisation)
    throw nurbs::InputError(where + "generalisation" + body_fitted +
                            "sides (its load suite); list fit_load_cases and "
                            "holdout_load_cases instead");
  if (request.load_suite)
    throw nurbs::InputError(where + "load_suite" + body_fitted +
                            "sides; write the load cases into the case file instead");
  const auto asked = [&](const char* key) {
    return calibration.is_object() && calibration.contains(key) && calibration.at(key) == true;
  };
  if (asked("matrix_approach"))
    throw nurbs::InputError(where + "matrix_approach" + body_fitted +
                            "IGA stiffness on the spring model's nodes; set it false");
  if (asked("acceleration_objective"))
    throw nurbs::InputError(where + "acceleration_objective" + body_fitted +
                            "consistent mass and stiffness; set it false");
  request.matrix_approach = request.settings.matrix_approach = false;
  request.acceleration_objective = false;
  return request;
}

}  // namespace

std::vector<std::string> calibrate_immersed_output_files(const std::vector<std::string>& ids) {
  std::vector<std::string> names{"report.json", "report.md", "model.json", "springs.vtp",
                                 "result.vtp"};
  for (const auto& id : ids) names.push_back(id + "_errors.csv");
  return names;
}

ImmersedCalibrateResult run_calibrate_immersed(const ImmersedCase& c, const Progress& progress) {
  ImmersedCalibrateResult r;
  r.c = c;
  r.request = immersed_request(c);
  fitting::CalibrationSettings settings = r.request.settings;
  if (!progress.quiet()) {
    settings.progress = [&progress](const std::string& line) { progress(line); };
    settings.iteration = [&progress](const std::string& stage, int iteration, double cost) {
      progress.update(stage, iteration, cost);
    };
  }
  progress("immersing " + c.part.filename().string() + " (degree " +
           std::to_string(c.immersion.degree) + ")");
  const auto t = std::chrono::steady_clock::now();
  r.domain = geometry::immerse_solid(*c.cad, c.immersion, &r.stats);
  r.immersion_seconds = seconds_since(t);
  r.occ = geometry::measure_solid(*c.cad);
  r.quadrature = geometry::measure_quadrature(r.domain);
  for (const std::string& w : r.domain.warnings) progress.warn(w);
  progress(std::to_string(r.stats.inside_cells) + " inside and " +
           std::to_string(r.stats.cut_cells) + " cut cells in " +
           format_number(r.immersion_seconds, 3) + " s");

  std::vector<fitting::ImmersedCalibrationCase> cases;
  for (const ImmersedLoadCase& load : c.load_cases)
    cases.push_back({load.id, immersed_options(c, load)});
  r.calibration = fitting::calibrate_immersed(r.domain, cases, settings);
  const fitting::CalibrationResult& result = r.calibration.calibration;
  for (const auto& e : result.fit)
    r.worst_fitted = std::max(r.worst_fitted, e.control.percent_e_rms);
  for (const auto& e : result.holdout)
    r.worst_holdout = std::max(r.worst_holdout, e.control.percent_e_rms);
  r.worst = std::max(r.worst_fitted, r.worst_holdout);
  if (r.request.target_percent_e_rms > 0.0 && r.worst > r.request.target_percent_e_rms)
    r.calibration.calibration.warnings.push_back(
        "the worst %e_rms over fitted and held-out load cases (" + format_number(r.worst, 3) +
        ") exceeds target_percent_e_rms " + format_number(r.request.target_percent_e_rms, 3) +
        ": the spring model does not reach the reference on every load");
  for (const auto& warning : result.mesh.warnings) progress.warn(warning);
  for (const auto& warning : result.warnings) progress.warn(warning);
  return r;
}

}  // namespace isospring::workflows
