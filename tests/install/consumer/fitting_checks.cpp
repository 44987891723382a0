// calibrate and identify from a consumer of the installed package: the same library calls the
// program makes, so the numbers must be the program's to 1e-12. This also links Ceres, a private
// dependency of isospring::fitting, through the package.
#include "fitting_checks.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <isospring/fitting/calibration.hpp>
#include <isospring/fitting/identify.hpp>
#include <isospring/io/case_file.hpp>
#include <isospring/io/case_refinement_ladder.hpp>
#include <isospring/io/markers.hpp>
#include <nlohmann/json.hpp>

namespace consumer {
namespace {

nlohmann::json read_json(const char* file) {
  std::ifstream in(file);
  return nlohmann::json::parse(in);
}

bool same_metrics(const std::vector<isospring::fitting::CaseErrors>& ours,
                  const nlohmann::json& reported) {
  bool ok = reported.at("load_cases").size() == ours.size();
  for (size_t i = 0; ok && i < ours.size(); ++i) {
    const nlohmann::json& r = reported.at("load_cases").at(i);
    ok = r.at("id") == ours[i].id && ok;
    ok = agrees(ours[i].id + " %e_rms", ours[i].control.percent_e_rms, r.at("percent_e_rms")) && ok;
    ok = agrees(ours[i].id + " field %e_rms", ours[i].field.percent_e_rms,
                r.at("field_percent_e_rms")) &&
         ok;
  }
  return ok;
}

}  // namespace

bool agrees(const std::string& what, double ours, double reported) {
  const double difference = std::abs(ours - reported) / std::max(std::abs(reported), 1e-300);
  std::printf("%s: %.17g (the program: %.17g, relative difference %.3g)\n", what.c_str(), ours,
              reported, difference);
  return difference <= 1e-12;
}

bool check_calibration(const char* case_file, const char* report_file) {
  const isospring::io::Case c = isospring::io::read_case_file(case_file);
  // The case's "calibration" object, field by field (the program parses it in apps/).
  const nlohmann::json& cal = c.calibration;
  isospring::fitting::CalibrationSettings settings;
  settings.gamma = cal.at("grouping").at("gamma");
  settings.per_spring = cal.at("grouping").at("per_spring");
  settings.regularization = cal.at("regularization");
  settings.fit_cases = cal.at("fit_load_cases").get<std::vector<std::string>>();
  settings.holdout_cases = cal.at("holdout_load_cases").get<std::vector<std::string>>();
  settings.damping_alpha = cal.at("damping_alpha");
  settings.matrix_approach = cal.at("matrix_approach");
  const isospring::fitting::CalibrationResult result =
      isospring::fitting::calibrate(c.problem, settings);
  const nlohmann::json report = read_json(report_file);
  std::printf("calibrate %s: %zu springs\n", c.name.c_str(), result.mesh.network.springs.size());
  bool ok = report.at("springs") == result.mesh.network.springs.size();
  ok = same_metrics(result.fit, report.at("fit")) && ok;
  return same_metrics(result.holdout, report.at("holdout")) && ok;
}

bool check_identification(const char* case_file, const char* report_file) {
  const isospring::io::Case c = isospring::io::read_case_file(case_file);
  std::vector<std::string> ids;
  for (const auto& load : c.problem.load_cases) ids.push_back(load.id);
  const isospring::io::MeasurementSettings settings = isospring::io::read_measurement_settings(
      c.measurements.value().raw, c.file.parent_path(), c.dimension, ids, "measurements");
  const isospring::fitting::Measurements data =
      isospring::io::read_markers_csv(settings.file, settings.file_options);
  // The program's default tolerance: 1e-3 of the control nets' bounding-box diagonal.
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (const auto& p : c.problem.patches) {
    lo = lo.cwiseMin(p.control_bounds().first);
    hi = hi.cwiseMax(p.control_bounds().second);
  }
  const isospring::fitting::PlacementResult placed = isospring::fitting::place_markers(
      c.problem.patches, data.markers,
      settings.placement_tolerance.value_or(1e-3 * (hi - lo).norm()));
  isospring::fitting::IdentifyOptions options = settings.identify;
  options.discretization.ladder = isospring::io::case_refinement_ladder(c);
  const isospring::fitting::IdentifyResult result =
      isospring::fitting::identify(c.problem, data.markers, placed.placements, options);

  const nlohmann::json report = read_json(report_file);
  std::string effects;
  for (const auto& e : result.effects_added) effects += " " + e;
  std::printf("identify %s: %zu markers, effects added:%s\n", c.name.c_str(), data.markers.size(),
              effects.c_str());
  bool ok = placed.outside.empty() && report.at("effects_added") == result.effects_added;
  ok = agrees("rms_after", result.after.rms, report.at("rms_after")) && ok;
  ok = report.at("parameters").size() == result.parameters.size() && ok;
  for (size_t i = 0; ok && i < result.parameters.size(); ++i)
    ok = agrees(result.parameters[i].name, result.parameters[i].value,
                report.at("parameters").at(i).at("value")) &&
         ok;
  return ok;
}

}  // namespace consumer
