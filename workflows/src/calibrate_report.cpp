// report.json, report.md and model.json of `isospring calibrate` (see calibrate_command.hpp).
#include <algorithm>
#include <cmath>

#include "isospring/io/report_case.hpp"
#include "isospring/workflows/calibrate_command.hpp"

namespace isospring::workflows {
// The use cases read and write io's formats; io's names are used unqualified here.
using namespace isospring::io;

nlohmann::json case_errors_json(const fitting::CaseErrors& e) {
  return {{"id", e.id},
          {"percent_e_rms", e.control.percent_e_rms},
          {"percent_e_max", e.control.percent_e_max},
          {"o_max", e.control.o_max},
          {"field_percent_e_rms", e.field.percent_e_rms},
          {"field_percent_e_max", e.field.percent_e_max},
          {"surface_percent_e_rms", e.surface.percent_e_rms},
          {"surface_percent_e_max", e.surface.percent_e_max}};
}

namespace {

// Root mean square of %e_rms and the largest %e_max over a set of cases.
nlohmann::json summary_json(const std::vector<fitting::CaseErrors>& cases) {
  if (cases.empty()) return nullptr;
  double sum = 0.0, worst = 0.0;
  for (const auto& e : cases) {
    sum += e.control.percent_e_rms * e.control.percent_e_rms;
    worst = std::max(worst, e.control.percent_e_max);
  }
  nlohmann::json out = {{"percent_e_rms", std::sqrt(sum / static_cast<double>(cases.size()))},
                        {"percent_e_max", worst},
                        {"load_cases", nlohmann::json::array()}};
  for (const auto& e : cases) out["load_cases"].push_back(case_errors_json(e));
  return out;
}

std::string protocol_text(const fitting::CalibrationSettings& s,
                          const fitting::CalibrationResult& r) {
  std::string text = "Displacement objective [S15 5.7] summed over the fitted load cases; ";
  text += s.per_spring && s.prior_weight > 0.0
              ? "one stiffness per spring (" + std::to_string(r.parameters) +
                    " parameters, L-BFGS, log k pulled towards the gamma " +
                    format_number(r.gamma) + " grouped optimum with weight " +
                    format_number(s.prior_weight) + ")"
          : s.per_spring
              ? "one stiffness per spring (" + std::to_string(r.parameters) +
                    " parameters, regularisation weight " + format_number(s.regularization) + ")"
              : "springs grouped by rest length, gamma " + format_number(r.gamma) + " (" +
                    std::to_string(r.parameters) + " groups)";
  if (!s.gamma_sweep.empty())
    text += ", best of a sweep over " + std::to_string(s.gamma_sweep.size()) + " gamma values";
  if (s.mesh.reach == 2) text += "; springs also two net steps apart (reach 2)";
  if (s.mesh.strain_points > 0)
    text += "; a volume and a shear strain-point term at " + std::to_string(s.mesh.strain_points) +
            " Gauss point(s) per direction of every knot span";
  text +=
      "; Levenberg-Marquardt on log-stiffnesses with the analytic Jacobian. Errors are on the "
      "control points (o_max: largest reference control-point displacement).";
  return text;
}

std::string large_deformation_protocol(const fitting::CalibrationResult& r,
                                       const LargeDeformationSummary& large) {
  std::string amplitudes;
  for (double a : large.amplitudes)
    amplitudes += (amplitudes.empty() ? "" : ", ") + format_number(a);
  return "Large-deformation calibration: every fitted load case scaled to %eps_G " + amplitudes +
         " (mean spring stretch of the control net under the linear solution) and solved by the " +
         large.law + " IGA; springs grouped by rest length, gamma " + format_number(r.gamma) +
         " (" + std::to_string(r.parameters) +
         " groups), fitted by Levenberg-Marquardt on log-stiffnesses to the finite-strain "
         "displacements with the springs' nonlinear static equilibrium as the response "
         "(implicit-function Jacobian), continued from each amplitude to the next, starting "
         "from the linear fit to the same references. Held-out cases are taken as given and "
         "solved by the same law. Errors are on the control points (o_max: largest reference "
         "control-point displacement).";
}

nlohmann::json large_deformation_json(const LargeDeformationSummary& large) {
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& row : large.rows)
    rows.push_back({{"amplitude", row.amplitude},
                    {"cases", row.cases},
                    {"worst_percent_e_rms", row.worst_percent_e_rms},
                    {"percent_e_rms", row.percent_e_rms},
                    {"reference_percent_eps_g", row.reference_percent_eps_g},
                    {"linear_start_worst_percent_e_rms", row.start_worst_percent_e_rms},
                    {"linear_start_without_equilibrium", row.start_without_equilibrium}});
  return {{"law", large.law},
          {"amplitudes", large.amplitudes},
          {"reached_amplitude", large.reached_amplitude},
          {"stopped", large.stopped.empty() ? nlohmann::json() : nlohmann::json(large.stopped)},
          {"per_amplitude", rows},
          {"holdout_without_equilibrium", large.holdout_without_equilibrium}};
}

}  // namespace

nlohmann::json calibrate_report_json(const CalibrateCommandResult& r) {
  const fitting::CalibrationResult& result = r.calibration;
  const fitting::CalibrationSettings& settings = r.request.settings;
  const analysis::SpringNetwork& network = result.mesh.network;
  const CalibrationRequest& request = r.request;
  const std::optional<fitting::MatrixComparison>& acceleration = r.acceleration;
  const double worst_fitted = r.worst_fitted, worst_holdout = r.worst_holdout, worst = r.worst;
  const std::optional<fitting::GeneralisationResult>& generalisation = r.generalisation;
  nlohmann::json report = report_header("calibrate", isospring_version(), r.input);
  report["case"] = r.case_summary;
  report["protocol"] = r.large_deformation
                           ? large_deformation_protocol(result, *r.large_deformation)
                           : protocol_text(settings, result);
  report["large_deformation"] =
      r.large_deformation ? large_deformation_json(*r.large_deformation) : nlohmann::json();
  report["particles"] = network.positions.size();
  report["springs"] = network.springs.size();
  // Net-cell terms; a strain point (one volume and one shear term) is counted apart.
  report["volume_terms"] = std::count_if(
      network.volumes.begin(), network.volumes.end(),
      [](const auto& t) { return t.kind == analysis::CellEnergy::kVolume && t.points.empty(); });
  report["shear_terms"] = std::count_if(
      network.volumes.begin(), network.volumes.end(),
      [](const auto& t) { return t.kind == analysis::CellEnergy::kShear && t.points.empty(); });
  report["strain_points"] = std::count_if(
      network.volumes.begin(), network.volumes.end(),
      [](const auto& t) { return t.kind == analysis::CellEnergy::kShear && !t.points.empty(); });
  report["groups"] = result.parameters;
  report["groups_at_lower_bound"] = result.fit_result.groups_at_lower_bound;
  report["warnings"] = result.mesh.warnings;
  for (const auto& warning : result.warnings) report["warnings"].push_back(warning);
  report["gamma"] = result.gamma;
  report["per_spring"] = settings.per_spring;
  report["iterations"] = result.fit_result.iterations;
  report["final_cost"] = result.fit_result.cost;
  report["termination"] = result.fit_result.message;
  report["fit_seconds"] = result.fit_seconds;
  report["reference_seconds"] = result.reference_seconds;
  const nlohmann::json fitted = summary_json(result.fit);
  report["percent_e_rms"] = fitted["percent_e_rms"];
  report["percent_e_max"] = fitted["percent_e_max"];
  report["fit"] = fitted;
  report["holdout"] = summary_json(result.holdout);
  report["worst_fitted_percent_e_rms"] = worst_fitted;
  report["worst_holdout_percent_e_rms"] =
      result.holdout.empty() ? nlohmann::json() : nlohmann::json(worst_holdout);
  report["worst_percent_e_rms"] = worst;
  report["target_percent_e_rms"] =
      request.target_percent_e_rms > 0.0 ? nlohmann::json(request.target_percent_e_rms) : nullptr;
  report["meets_target"] = request.target_percent_e_rms > 0.0
                               ? nlohmann::json(worst <= request.target_percent_e_rms)
                               : nullptr;
  report["generalisation"] = nullptr;
  if (generalisation) {
    const auto& chosen = generalisation->candidates[static_cast<size_t>(generalisation->chosen)];
    nlohmann::json g = {{"reach", chosen.reach},
                        {"volume_terms", chosen.volume_terms},
                        {"shear_terms", chosen.shear_terms},
                        {"strain_points", chosen.strain_points},
                        {"gamma", chosen.gamma},
                        {"prior_weight", chosen.prior_weight},
                        {"cross_validation_worst", chosen.worst},
                        {"folds", request.generalisation->folds},
                        {"candidates", nlohmann::json::array()}};
    for (const auto& cand : generalisation->candidates)
      g["candidates"].push_back({{"reach", cand.reach},
                                 {"volume_terms", cand.volume_terms},
                                 {"shear_terms", cand.shear_terms},
                                 {"strain_points", cand.strain_points},
                                 {"gamma", cand.gamma},
                                 {"prior_weight", cand.prior_weight},
                                 {"parameters", cand.parameters},
                                 {"cross_validation_worst", cand.worst},
                                 {"failure", cand.failure}});
    report["generalisation"] = g;
  }
  report["sweep"] = nlohmann::json::array();
  // Per gamma (fitting::SweepEntry): the fit's %e_rms and %e_max over the fitted cases, the
  // stiffnesses fitted, why the gamma failed ("" when it did not) and, when its grouping repeats
  // an earlier gamma's, that gamma (null: fitted).
  for (const auto& entry : result.sweep)
    report["sweep"].push_back(
        {{"gamma", entry.gamma},
         {"groups", entry.groups},
         {"percent_e_rms", entry.percent_e_rms},
         {"percent_e_max", entry.percent_e_max},
         {"parameters", entry.parameters},
         {"failure", entry.failure},
         {"reused_from_gamma", entry.reused_from < 0
                                   ? nlohmann::json(nullptr)
                                   : nlohmann::json(result.sweep[entry.reused_from].gamma)}});
  report["matrix_approach"] = nlohmann::json::array();
  for (const auto& m : result.matrix)
    report["matrix_approach"].push_back(
        {{"method", m.method},
         {"relative_frobenius_residual", m.fit.relative_residual},
         {"negative_springs", m.fit.negative_springs},
         {"seconds", m.fit.seconds},
         {"fit", m.solved ? summary_json(m.fit_cases) : nlohmann::json(nullptr)},
         {"holdout", m.solved ? summary_json(m.holdout) : nlohmann::json(nullptr)}});

  report["acceleration_objective"] = nullptr;
  // The baseline is evaluated on the control points only (no field metrics).
  auto control_only = [](nlohmann::json summary) {
    if (summary.is_object())
      for (auto& e : summary["load_cases"]) {
        e.erase("field_percent_e_rms");
        e.erase("field_percent_e_max");
        e.erase("surface_percent_e_rms");
        e.erase("surface_percent_e_max");
      }
    return summary;
  };
  if (acceleration)
    report["acceleration_objective"] = {
        {"groups", acceleration->fit.group_stiffness.size()},
        {"relative_residual", acceleration->fit.relative_residual},
        {"springs_at_zero", acceleration->fit.negative_springs},
        {"seconds", acceleration->fit.seconds},
        {"fit", acceleration->solved ? control_only(summary_json(acceleration->fit_cases))
                                     : nlohmann::json()},
        {"holdout", acceleration->solved ? control_only(summary_json(acceleration->holdout))
                                         : nlohmann::json()}};
  return report;
}

SpringModel calibrate_spring_model(const CalibrateCommandResult& r, const nlohmann::json& report) {
  const fitting::CalibrationResult& result = r.calibration;
  const fitting::CalibrationSettings& settings = r.request.settings;
  const analysis::SpringNetwork& network = result.mesh.network;
  nlohmann::json provenance = {{"case", r.case_name},
                               {"isospring_version", isospring_version()},
                               {"fit",
                                {{"objective", "displacement"},
                                 {"percent_e_rms", report["percent_e_rms"]},
                                 {"percent_e_max", report["percent_e_max"]},
                                 {"groups", result.parameters},
                                 {"gamma", result.gamma}}}};
  // How the springs' c was set, so a reader of model.json can tell alpha from zeta.
  if (settings.damping_alpha > 0.0)
    provenance["damping"] = {{"alpha", settings.damping_alpha}};
  else if (settings.damping_ratio > 0.0)
    provenance["damping"] = {{"ratio", settings.damping_ratio}};
  else
    provenance["damping"] = nullptr;
  // With its load cases (the loads it was fitted and evaluated under): `simulate` runs from it.
  SpringModel model;
  model.network = network;
  model.provenance = provenance;
  model.units = default_model_units();
  for (size_t l = 0; l < result.particle_loads.size(); ++l)
    model.load_cases.push_back(
        model_load_case(result.load_ids[l], result.particle_loads[l], network.dimension));
  return model;
}

MarkdownReport calibrate_report_markdown(const CalibrateCommandResult& r,
                                         const nlohmann::json& report,
                                         const std::vector<std::string>& figures) {
  const fitting::CalibrationResult& result = r.calibration;
  const analysis::SpringNetwork& network = result.mesh.network;
  const CalibrationRequest& request = r.request;
  const std::optional<fitting::MatrixComparison>& acceleration = r.acceleration;
  const double worst_fitted = r.worst_fitted, worst_holdout = r.worst_holdout, worst = r.worst;
  MarkdownReport md;
  md.heading(1, "isospring calibrate: " + r.case_name);
  add_case_summary(md, report["case"]);
  md.heading(2, "Protocol");
  md.paragraph(report["protocol"].get<std::string>());
  md.heading(2, "Errors");
  md.paragraph("Worst %e_rms: " + format_number(worst_fitted, 4) + " over the fitted cases, " +
               (result.holdout.empty()
                    ? std::string("no held-out cases")
                    : format_number(worst_holdout, 4) + " over the held-out cases") +
               (request.target_percent_e_rms > 0.0
                    ? "; target " + format_number(request.target_percent_e_rms, 4) +
                          (worst <= request.target_percent_e_rms ? " (met)." : " (**not met**).")
                    : "."));
  if (!report["warnings"].empty()) {
    std::vector<std::string> items;
    for (const auto& w : report["warnings"]) items.push_back("Warning: " + w.get<std::string>());
    md.bullets(items);
  }
  std::vector<std::vector<std::string>> rows;
  for (const auto* cases : {&result.fit, &result.holdout})
    for (const auto& e : *cases)
      rows.push_back(
          {e.id, cases == &result.fit ? "fitted" : "held out",
           format_number(e.control.percent_e_rms, 4), format_number(e.control.percent_e_max, 4),
           format_number(e.field.percent_e_rms, 4), format_number(e.surface.percent_e_rms, 4),
           format_number(e.surface.percent_e_max, 4), "`" + e.id + "_errors.csv`"});
  md.table({"load case", "role", "%e_rms", "%e_max", "field %e_rms", "surface %e_rms",
            "surface %e_max", "errors"},
           rows);
  md.paragraph(
      "%e_rms / %e_max on the control points [S15 4.20-4.21]; field: the NURBS displacement "
      "fields of both models sampled over the whole parameter domain; surface: sampled on the "
      "boundary faces of volume patches without interfaces, seams and collapsed sides (in 2D "
      "the membrane is the surface: the field values), what a viewer or a marker sees.");
  if (r.large_deformation) {
    md.heading(2, "Large deformation: per amplitude");
    std::vector<std::vector<std::string>> arows;
    for (const auto& row : r.large_deformation->rows)
      arows.push_back(
          {format_number(row.amplitude), format_number(row.reference_percent_eps_g, 3),
           std::to_string(row.cases), format_number(row.worst_percent_e_rms, 4),
           format_number(row.percent_e_rms, 4),
           format_number(row.start_worst_percent_e_rms, 4) +
               (row.start_without_equilibrium > 0
                    ? " (" + std::to_string(row.start_without_equilibrium) + " without equilibrium)"
                    : "")});
    md.table({"target %eps_G", "reference %eps_G", "fitted cases", "worst %e_rms", "rms %e_rms",
              "worst %e_rms of the linear start"},
             arows);
    md.paragraph(
        "Fitted cases \"id@a\": the case scaled to %eps_G a, solved by the " +
        r.large_deformation->law +
        " IGA; the spring model's response is its nonlinear static equilibrium. The linear "
        "start is the linear fit to the same references, also by its nonlinear equilibrium." +
        (r.large_deformation->stopped.empty() ? std::string()
                                              : " Stopped: " + r.large_deformation->stopped));
  }
  md.paragraph(std::to_string(network.positions.size()) + " particles, " +
               std::to_string(network.springs.size()) + " springs, " +
               std::to_string(result.parameters) + " stiffness parameters; " +
               std::to_string(result.fit_result.iterations) + " iterations, final cost " +
               format_number(result.fit_result.cost) + ", fit " +
               format_number(result.fit_seconds, 3) + " s.");
  if (!result.matrix.empty()) {
    md.heading(2, "Matrix approach (Frobenius) on the same springs");
    std::vector<std::vector<std::string>> mrows;
    for (const auto& m : result.matrix) {
      const nlohmann::json errors = m.solved ? summary_json(m.fit_cases) : nlohmann::json();
      auto cell = [&](const char* key) {
        return errors.is_null() ? std::string("singular")
                                : format_number(errors[key].get<double>(), 4);
      };
      mrows.push_back({m.method, format_number(m.fit.relative_residual, 4),
                       std::to_string(m.fit.negative_springs), cell("percent_e_rms"),
                       cell("percent_e_max")});
    }
    md.table({"method", "rel. Frobenius residual", "negative springs", "%e_rms (fitted cases)",
              "%e_max (fitted cases)"},
             mrows);
  }
  if (acceleration) {
    md.heading(2, "Acceleration objective [S15 4.1-4.5] on the same springs");
    const nlohmann::json& a = report["acceleration_objective"];
    auto cell = [&](const char* part, const char* key) {
      return a[part].is_null() || a[part].empty()
                 ? std::string(acceleration->solved ? "-" : "singular")
                 : format_number(a[part][key].get<double>(), 4);
    };
    md.table({"groups", "rel. residual", "springs at k = 0", "%e_rms (fitted)", "%e_max (fitted)",
              "%e_rms (held out)"},
             {{std::to_string(acceleration->fit.group_stiffness.size()),
               format_number(acceleration->fit.relative_residual, 4),
               std::to_string(acceleration->fit.negative_springs), cell("fit", "percent_e_rms"),
               cell("fit", "percent_e_max"), cell("holdout", "percent_e_rms")}});
    md.paragraph(
        "min over k >= 0 of the spring-force residual M^-1 (K_NMSM(k) u_ref - f) of the IGA "
        "displacements (static reference: a_ref = 0), a linear problem; its model is then "
        "evaluated like the displacement fit.");
  }
  if (result.sweep.size() > 1) {
    md.heading(2, "Gamma sweep");
    std::vector<std::vector<std::string>> srows;
    for (const auto& entry : result.sweep)
      srows.push_back({format_number(entry.gamma), std::to_string(entry.groups),
                       format_number(entry.percent_e_rms, 4),
                       !entry.failure.empty() ? "failed: " + entry.failure
                       : entry.reused_from >= 0
                           ? "grouping of gamma " +
                                 format_number(result.sweep[entry.reused_from].gamma) +
                                 " (fit reused)"
                       : entry.gamma == result.gamma ? "kept"
                                                     : ""});
    md.table({"gamma", "groups", "%e_rms (fitted cases)", "note"}, srows);
  }
  md.heading(2, "Outputs");
  md.paragraph("ParaView: `result.vtm` (geometry and control net with `reference_<id>`, " +
               std::string("`model_<id>` and `error_<id>` (model - reference) per load case; ") +
               "springs with `model_<id>` and `error_<id>` per particle). `model.json`: the " +
               "calibrated model for `isospring export` and `isospring simulate`.");
  for (const std::string& figure : figures) md.paragraph("![" + figure + "](" + figure + ")");
  return md;
}

}  // namespace isospring::workflows
