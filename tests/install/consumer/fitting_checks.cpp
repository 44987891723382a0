// calibrate and identify from a consumer of the installed package: the same library calls the
// program makes, so the numbers must be the program's to 1e-12. This also links Ceres, a private
// dependency of isospring::fitting, through the package.
#include "fitting_checks.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <isospring/io/case_file.hpp>
#include <isospring/workflows/calibrate_command.hpp>
#include <isospring/workflows/identify_command.hpp>
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
  // workflows::run_calibrate: the call `isospring calibrate` makes, "calibration" object included.
  const isospring::io::Progress progress("calibrate", true);
  const isospring::workflows::CalibrateCommandResult r =
      isospring::workflows::run_calibrate(isospring::io::read_case_file(case_file), progress);
  const isospring::fitting::CalibrationResult& result = r.calibration;
  const nlohmann::json report = read_json(report_file);
  std::printf("calibrate %s: %zu springs\n", r.case_name.c_str(),
              result.mesh.network.springs.size());
  bool ok = report.at("springs") == result.mesh.network.springs.size();
  ok = same_metrics(result.fit, report.at("fit")) && ok;
  ok = same_metrics(result.holdout, report.at("holdout")) && ok;
  // The library's report.json holds the same numbers (not the timings).
  const nlohmann::json ours = isospring::workflows::calibrate_report_json(r);
  return agrees("percent_e_rms (report)", ours.at("percent_e_rms"), report.at("percent_e_rms")) &&
         ok;
}

bool check_identification(const char* case_file, const char* report_file) {
  // workflows::run_identify: the call `isospring identify` makes (marker placement, the loop, the
  // recalibration of the spring model).
  const isospring::io::Progress progress("identify", true);
  const isospring::workflows::IdentifyCommandResult r =
      isospring::workflows::run_identify(isospring::io::read_case_file(case_file), {}, progress);
  const isospring::fitting::IdentifyResult& result = r.identify;

  const nlohmann::json report = read_json(report_file);
  std::string effects;
  for (const auto& e : result.effects_added) effects += " " + e;
  std::printf("identify %s: %zu markers, effects added:%s\n", r.case_name.c_str(), r.markers.size(),
              effects.c_str());
  bool ok = r.dropped.empty() && report.at("effects_added") == result.effects_added;
  ok = agrees("rms_after", result.after.rms, report.at("rms_after")) && ok;
  ok = report.at("parameters").size() == result.parameters.size() && ok;
  for (size_t i = 0; ok && i < result.parameters.size(); ++i)
    ok = agrees(result.parameters[i].name, result.parameters[i].value,
                report.at("parameters").at(i).at("value")) &&
         ok;
  if (r.recalibration)
    ok = agrees("recalibration percent_e_rms", r.recalibration->percent_e_rms,
                report.at("recalibration").at("percent_e_rms")) &&
         ok;
  return ok;
}

}  // namespace consumer
