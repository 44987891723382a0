// report.json and report.md of `isospring identify` (see identify_command.hpp).
#include <cmath>

#include "isospring/io/report_case.hpp"
#include "isospring/io/report_discretization.hpp"
#include "isospring/workflows/identify_command.hpp"

namespace isospring::workflows {
// The use cases read and write io's formats; io's names are used unqualified here.
using namespace isospring::io;
namespace {

nlohmann::json errors_json(const fitting::ErrorSummary& e) {
  return {{"rms", e.rms}, {"max", e.max}, {"max_norm", e.max_norm}};
}

nlohmann::json vector_json(const Eigen::Vector3d& v, int dim) {
  nlohmann::json j = nlohmann::json::array();
  for (int c = 0; c < dim; ++c) j.push_back(v[c]);
  return j;
}

nlohmann::json residual_json(const fitting::ResidualDescription& d) {
  const int dim = d.dimension;
  nlohmann::json j{
      {"rms", d.rms},
      {"component_rms", vector_json(d.component_rms, dim)},
      {"constant_fraction", d.constant_fraction},
      {"linear_fraction", d.linear_fraction},
      {"noise_fraction", d.noise_fraction},
      {"load_correlation", std::isnan(d.load_correlation) ? nlohmann::json(nullptr)
                                                          : nlohmann::json(d.load_correlation)},
      {"summary", d.summary}};
  for (const auto& c : d.load_cases)
    j["load_cases"].push_back({{"id", c.id},
                               {"markers", c.markers},
                               {"rms", c.rms},
                               {"component_rms", vector_json(c.component_rms, dim)},
                               {"load_norm", c.load_norm},
                               {"resultant", vector_json(c.resultant, dim)},
                               {"rms_per_load", c.rms_per_load}});
  return j;
}

// The estimates under `key`; no key at all when there are none (report.json has always been so).
void add_parameters(nlohmann::json& report, const char* key,
                    const std::vector<fitting::ParameterEstimate>& parameters) {
  for (const auto& p : parameters)
    report[key].push_back({{"effect", p.effect},
                           {"name", p.name},
                           {"unit", p.unit},
                           {"value", p.value},
                           {"standard_error", p.standard_error}});
}

// The residual description as a table and a sentence (report.md).
void residual_markdown(MarkdownReport& md, const std::string& title,
                       const fitting::ResidualDescription& d) {
  const int dim = d.dimension;
  auto components = [dim](const Eigen::Vector3d& v) {
    std::string s;
    for (int c = 0; c < dim; ++c) s += (c ? ", " : "") + format_number(v[c], 3);
    return s;
  };
  std::vector<std::vector<std::string>> rows;
  rows.push_back({"all", format_number(d.rms, 3), components(d.component_rms), "", ""});
  for (const auto& c : d.load_cases)
    rows.push_back({c.id, format_number(c.rms, 3), components(c.component_rms),
                    format_number(c.load_norm, 3), format_number(c.rms_per_load, 3)});
  md.paragraph(title + ": " + d.summary);
  md.table({"load case", "rms [m]", "rms per component [m]", "|f| [N]", "rms / |f| [m/N]"}, rows);
}

}  // namespace

nlohmann::json identify_report_json(const IdentifyCommandResult& result) {
  const fitting::IdentifyResult& r = result.identify;
  const MeasurementSettings& settings = result.settings;
  const std::vector<fitting::Marker>& kept = result.markers;
  const double tolerance = result.placement_tolerance;
  const fitting::IdentifyOptions& identify_options = result.identify_options;
  const std::optional<fitting::Recalibration>& recalibration = result.recalibration;
  const std::string& recalibration_error = result.recalibration_error;
  nlohmann::json report = report_header("identify", isospring_version(), result.input);
  report["case"] = result.case_summary;
  report["data_file"] = settings.file.string();
  report["markers"] = kept.size();
  report["markers_dropped"] = nlohmann::json::array();
  for (const auto& d : result.dropped)
    report["markers_dropped"].push_back(
        {{"row", d.row}, {"load_case", d.load_case}, {"distance", d.distance}});
  report["placement_tolerance"] = tolerance;
  report["discretization"] = discretization_json(r.discretization, r.discretization_allowance);
  report["effects_added"] = r.effects_added;
  add_parameters(report, "parameters", r.parameters);
  add_parameters(report, "parameters_before", r.parameters_before);
  for (const auto& [name, value] : r.derived) report["derived"][name] = value;
  report["residual_before"] = residual_json(r.residual_before);
  report["residual_after"] = residual_json(r.residual_after);
  report["rms_before"] = r.before.rms;
  report["rms_after"] = r.after.rms;
  report["max_before"] = r.before.max;
  report["max_after"] = r.after.max;
  report["max_norm_before"] = r.before.max_norm;
  report["max_norm_after"] = r.after.max_norm;
  report["noise_estimate"] = r.noise_estimate;
  report["noise_given"] = r.noise_given;
  report["chi2_per_dof_before"] = r.chi2_before;
  report["chi2_per_dof_after"] = r.chi2_after;
  report["observations"] = r.observations;
  for (const auto& lc : r.load_cases)
    report["load_cases"].push_back({{"id", lc.id},
                                    {"markers", lc.markers},
                                    {"before", errors_json(lc.before)},
                                    {"after", errors_json(lc.after)}});
  for (const auto& round : r.rounds) {
    nlohmann::json j{{"rss", round.rss},
                     {"added", round.added},
                     {"removed", round.removed},
                     {"residual", residual_json(round.residual)}};
    for (const auto& t : round.candidates) {
      j["candidates"].push_back({{"effect", t.effect},
                                 {"parameters", t.parameters},
                                 {"rss", t.rss},
                                 {"f", t.f_statistic},
                                 {"p_value", t.p_value},
                                 {"delta_bic", t.delta_bic},
                                 {"score_f", t.score_f},
                                 {"model_error_allowance", t.model_error_allowance},
                                 {"seconds", t.seconds},
                                 {"note", t.note}});
      if (!t.expected_parameter.empty())
        j["candidates"].back()["expected_parameter"] = {{"name", t.expected_parameter},
                                                        {"estimate", t.expected_estimate},
                                                        {"standard_error", t.expected_error}};
    }
    report["selection"].push_back(j);
  }
  report["alternatives"] = nlohmann::json::array();
  for (const auto& a : r.alternatives)
    report["alternatives"].push_back({{"replaced", a.replaced},
                                      {"by", a.by},
                                      {"delta_bic", a.delta_bic},
                                      {"swapped", a.swapped}});
  report["selection_rule"] = "F-test, significance " +
                             format_number(identify_options.significance) +
                             " / (candidates in the round), ties (p underflowing to 0) broken by "
                             "the lower BIC; backward step at the same level";
  if (r.holdout_done)
    report["holdout"] = {{"fit_markers", r.holdout.fit_markers},
                         {"validation_markers", r.holdout.validation_markers},
                         {"validation_before", errors_json(r.holdout.validation_before)},
                         {"validation_after", errors_json(r.holdout.validation_after)}};
  for (const auto& h : r.load_case_holdout)
    report["load_case_holdout"].push_back({{"id", h.id},
                                           {"markers", h.markers},
                                           {"local_parameters", h.local_parameters},
                                           {"before", errors_json(h.before)},
                                           {"after", errors_json(h.after)}});
  report["spring_model"] = r.spring_model_notes;
  if (recalibration) {
    const fitting::Recalibration& rc = *recalibration;
    nlohmann::json j{{"model", "model.json"},
                     {"percent_e_rms", rc.percent_e_rms},
                     {"percent_e_max", rc.percent_e_max},
                     {"gravity", {rc.gravity.x(), rc.gravity.y(), rc.gravity.z()}},
                     {"load_factors", rc.load_factors},
                     {"youngs_modulus", rc.corrected.material.youngs_modulus},
                     {"poisson_ratio", rc.corrected.material.poisson_ratio},
                     {"gamma", rc.calibration.gamma},
                     {"groups", rc.calibration.parameters},
                     {"notes", rc.notes},
                     {"warnings", rc.calibration.warnings}};
    for (const auto& e : rc.calibration.fit)
      j["load_cases"].push_back({{"id", e.id},
                                 {"percent_e_rms", e.control.percent_e_rms},
                                 {"percent_e_max", e.control.percent_e_max}});
    report["recalibration"] = j;
  } else {
    report["recalibration"] = {{"error", recalibration_error}};
  }
  report["seconds"] = r.seconds;
  return report;
}

MarkdownReport identify_report_markdown(const IdentifyCommandResult& result, bool figure) {
  const fitting::IdentifyResult& r = result.identify;
  const MeasurementSettings& settings = result.settings;
  const std::vector<fitting::Marker>& kept = result.markers;
  const double tolerance = result.placement_tolerance;
  const std::optional<fitting::Recalibration>& recalibration = result.recalibration;
  const std::string& recalibration_error = result.recalibration_error;
  MarkdownReport md;
  md.heading(1, "isospring identify: " + result.case_name);
  add_case_summary(md, result.case_summary);
  md.heading(2, "Data");
  md.paragraph(std::to_string(kept.size()) + " markers from `" + settings.file.string() + "`" +
               (result.dropped.empty()
                    ? std::string(".")
                    : ", " + std::to_string(result.dropped.size()) + " dropped (farther than " +
                          format_number(tolerance, 3) + " m from the model).") +
               " Noise level " + format_number(r.noise_estimate, 3) + " m (" +
               (r.noise_given ? "given" : "estimated from neighbouring residual differences") +
               ").");
  add_discretization(md, r.discretization, r.discretization_allowance);
  md.heading(2, "Effects");
  const bool none_tried = settings.identify.candidates && settings.identify.candidates->empty();
  md.paragraph(none_tried ? "None tried (measurements.effects is []): the nominal fit alone."
               : r.effects_added.empty()
                   ? "None significant: the nominal model explains the data to the noise level."
                   : "Added in order: " +
                         [&] {
                           std::string s;
                           for (const auto& e : r.effects_added) s += (s.empty() ? "" : ", ") + e;
                           return s;
                         }() +
                         ".");
  std::vector<std::vector<std::string>> rows;
  for (const auto& p : r.parameters_before)
    rows.push_back({"nominal model (before)", p.name, format_number(p.value),
                    format_number(p.standard_error, 3), p.unit});
  for (const auto& p : r.parameters)
    rows.push_back(
        {p.effect, p.name, format_number(p.value), format_number(p.standard_error, 3), p.unit});
  md.table({"effect", "parameter", "value", "std. error", "unit"}, rows);
  for (const auto& [name, value] : r.derived) md.bullets({name + " = " + format_number(value)});
  md.heading(2, "Errors");
  rows.clear();
  rows.push_back({"all", std::to_string(kept.size()), format_number(r.before.rms, 4),
                  format_number(r.after.rms, 4), format_number(r.before.max_norm, 4),
                  format_number(r.after.max_norm, 4)});
  for (const auto& lc : r.load_cases)
    rows.push_back({lc.id, std::to_string(lc.markers), format_number(lc.before.rms, 4),
                    format_number(lc.after.rms, 4), format_number(lc.before.max_norm, 4),
                    format_number(lc.after.max_norm, 4)});
  md.table({"load case", "markers", "rms before [m]", "rms after [m]", "max \\|r\\| before [m]",
            "max \\|r\\| after [m]"},
           rows);
  md.paragraph(
      "rms: over every component of every marker; max |r|: the longest residual vector, as in "
      "residuals.csv, residuals.svg and the marker .vtp files (report.json also has `max`, the "
      "largest single component).");
  md.paragraph("chi^2 per degree of freedom: " + format_number(r.chi2_before, 4) + " before, " +
               format_number(r.chi2_after, 4) + " after (1 is the noise level).");
  if (figure) md.paragraph("![rms before and after](errors_before_after.png)");
  if (r.holdout_done)
    md.paragraph("Hold-out (fit on every other marker, validate on the rest): validation rms " +
                 format_number(r.holdout.validation_before.rms, 4) + " m before, " +
                 format_number(r.holdout.validation_after.rms, 4) + " m after.");
  if (!r.load_case_holdout.empty()) {
    rows.clear();
    for (const auto& h : r.load_case_holdout)
      rows.push_back({h.id, std::to_string(h.markers), format_number(h.before.rms, 4),
                      format_number(h.after.rms, 4), std::to_string(h.local_parameters)});
    md.paragraph(
        "Leave one load case out (both models refitted without it, then predicting it; "
        "parameters of that load case alone, such as its own rigid motion or load "
        "factor, are fitted on it):");
    md.table({"held-out load case", "markers", "rms nominal", "rms with effects",
              "own parameters fitted"},
             rows);
  }
  md.heading(2, "Residual");
  md.paragraph(
      "Share of the residual energy in constant and linear functions of position per load case "
      "and component (rigid motions, uniform strain errors) against what pure noise would put "
      "there, per-component and per-load-case RMS, and RMS per unit load.");
  residual_markdown(md, "Nominal model", r.residual_before);
  residual_markdown(md, "Final model", r.residual_after);
  md.heading(2, "Selection");
  for (size_t k = 0; k < r.rounds.size(); ++k) {
    rows.clear();
    for (const auto& t : r.rounds[k].candidates)
      rows.push_back({t.effect, std::to_string(t.parameters), format_number(t.f_statistic, 4),
                      format_number(t.p_value, 3), format_number(t.delta_bic, 4), t.note});
    md.paragraph(
        "Round " + std::to_string(k + 1) + ": " +
        (r.rounds[k].added.empty() ? "nothing significant, stop" : "added " + r.rounds[k].added) +
        ". Residual before the round: " + r.rounds[k].residual.summary);
    md.table({"candidate", "parameters", "F", "p", "delta BIC", "note"}, rows);
  }
  if (!r.alternatives.empty()) {
    std::vector<std::string> lines;
    for (const auto& a : r.alternatives)
      lines.push_back(a.swapped
                          ? "swapped: " + a.by + " in place of " + a.replaced + " (delta BIC " +
                                format_number(a.delta_bic, 3) +
                                ": the same data explained with fewer parameters)"
                          : "cannot be told apart on these data: " + a.replaced + " or " + a.by +
                                " (delta BIC " + format_number(a.delta_bic, 3) + ", below 2)");
    md.paragraph(
        "Swap stage (each selected effect against every other linear candidate in its "
        "place, by BIC):");
    md.bullets(lines);
  }
  if (!r.spring_model_notes.empty()) {
    md.heading(2, "Carrying over to the spring model");
    md.bullets(r.spring_model_notes);
  }
  md.heading(2, "Recalibrated spring model");
  if (recalibration) {
    const fitting::Recalibration& rc = *recalibration;
    md.paragraph("`model.json`: the spring model recalibrated against the corrected reference (E " +
                 format_number(rc.corrected.material.youngs_modulus) + " Pa, nu " +
                 format_number(rc.corrected.material.poisson_ratio) +
                 ", the physical effects below): %e_rms " + format_number(rc.percent_e_rms, 4) +
                 " %, %e_max " + format_number(rc.percent_e_max, 4) +
                 " % on the control points (root mean square / largest over the load cases).");
    md.bullets(rc.notes);
  } else {
    md.paragraph("Recalibration failed: " + recalibration_error);
  }
  md.paragraph(
      "Plot: `residuals.svg` (data `residuals.csv`); VTK: `markers_<case>_before.vtp`, "
      "`markers_<case>_after.vtp`.");

  return md;
}

}  // namespace isospring::workflows
