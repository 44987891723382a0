// `isospring identify CASE.json -o OUTDIR [--drop-outside] [--quiet]`: the measured-data loop.
// Fits the case's model to the markers of `"measurements"`, adds the effects the residual calls
// for (fitting/identify.hpp), recalibrates the spring model against the corrected reference
// (fitting/identify_recalibration.hpp) and writes OUTDIR/report.json, report.md, model.json (with
// the carried gravity and load cases), markers_*.vtp (measured, model and residual per load case,
// before and after), residuals.svg (our own SVG: one row per load case) and
// errors_before_after.png (gnuplot, when present).
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <optional>

#include "calibration_settings.hpp"
#include "cli_util.hpp"
#include "command.hpp"
#include "isospring/fitting/identify.hpp"
#include "isospring/fitting/identify_recalibration.hpp"
#include "isospring/fitting/measure.hpp"
#include "isospring/io/atomic_file.hpp"
#include "isospring/io/case_file.hpp"
#include "isospring/io/case_refinement_ladder.hpp"
#include "isospring/io/markers.hpp"
#include "isospring/io/model_file.hpp"
#include "isospring/io/output_guard.hpp"
#include "isospring/io/plot.hpp"
#include "isospring/io/report.hpp"
#include "isospring/io/report_case.hpp"
#include "isospring/io/report_discretization.hpp"
#include "isospring/io/svg_scatter.hpp"
#include "isospring/io/vtk_markers.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::apps {
namespace {

struct IdentifyCommandOptions {
  std::string case_file;
  std::string output;
  bool drop_outside = false;
  bool quiet = false;
  std::optional<long> max_dofs;  // overrides measurements.max_dofs
  bool no_discretization_check = false;
};

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

// The residual description as a table and a sentence (report.md).
void residual_markdown(io::MarkdownReport& md, const std::string& title,
                       const fitting::ResidualDescription& d) {
  const int dim = d.dimension;
  auto components = [dim](const Eigen::Vector3d& v) {
    std::string s;
    for (int c = 0; c < dim; ++c) s += (c ? ", " : "") + io::format_number(v[c], 3);
    return s;
  };
  std::vector<std::vector<std::string>> rows;
  rows.push_back({"all", io::format_number(d.rms, 3), components(d.component_rms), "", ""});
  for (const auto& c : d.load_cases)
    rows.push_back({c.id, io::format_number(c.rms, 3), components(c.component_rms),
                    io::format_number(c.load_norm, 3), io::format_number(c.rms_per_load, 3)});
  md.paragraph(title + ": " + d.summary);
  md.table({"load case", "rms [m]", "rms per component [m]", "|f| [N]", "rms / |f| [m/N]"}, rows);
}

double model_diagonal(const std::vector<nurbs::Patch>& patches) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (const auto& p : patches) {
    const auto [a, b] = p.control_bounds();
    lo = lo.cwiseMin(a);
    hi = hi.cwiseMax(b);
  }
  return (hi - lo).norm();
}

// Residual magnitude at every marker before and after: residuals.csv and residuals.svg (markers
// at their x and y positions; a 3D case shows its markers projected on x-y).
void write_residual_plot(const std::filesystem::path& out_dir,
                         const std::vector<fitting::Marker>& markers,
                         const fitting::IdentifyResult& r) {
  const std::filesystem::path data = out_dir / "residuals.csv";
  io::write_file_atomically(data, [&](std::ostream& out) {
    out << "load_case,x,y,z,residual_before,residual_after\n";
    for (size_t m = 0; m < markers.size(); ++m)
      out << markers[m].load_case << "," << io::format_exact(markers[m].position.x()) << ","
          << io::format_exact(markers[m].position.y()) << ","
          << io::format_exact(markers[m].position.z()) << ","
          << io::format_exact((markers[m].displacement - r.model_before[m]).norm()) << ","
          << io::format_exact((markers[m].displacement - r.model_after[m]).norm()) << "\n";
  });
  // Small multiples (io/svg_scatter.hpp): one row per load case (its own colour scale, so a
  // case with small residuals is not hidden by one with large ones), before and after side by
  // side; the colour is |residual|, the column of residuals.csv.
  std::vector<io::ScatterRow> rows;
  for (const auto& lc : r.load_cases) {
    io::ScatterRow row;
    row.name = lc.id;
    for (const char* stage : {"before", "after"}) {
      const bool before = std::string(stage) == "before";
      const auto& model = before ? r.model_before : r.model_after;
      const fitting::ErrorSummary& e = before ? lc.before : lc.after;
      io::ScatterPanel panel;
      panel.column = stage;
      panel.title = lc.id + (before ? ", nominal model" : ", with effects") + ": rms " +
                    io::format_number(e.rms, 2) + " m, max |r| " +
                    io::format_number(e.max_norm, 2) + " m";
      for (size_t m = 0; m < markers.size(); ++m) {
        if (markers[m].load_case != lc.id) continue;
        panel.x.push_back(markers[m].position.x());
        panel.y.push_back(markers[m].position.y());
        panel.value.push_back((markers[m].displacement - model[m]).norm());
      }
      row.panels.push_back(std::move(panel));
    }
    rows.push_back(std::move(row));
  }
  io::ScatterGridOptions options;
  options.title = "Marker residuals per load case: before and after the identified effects";
  options.value_label = "|residual| [m]";
  io::write_scatter_grid_svg(out_dir / "residuals.svg", rows, options);
}

void write_markers(const std::filesystem::path& out_dir, const analysis::Problem& problem,
                   const std::vector<fitting::Marker>& markers, const fitting::IdentifyResult& r) {
  // One point set per load case with measured/model/residual; "before" and "after" files.
  for (const char* stage : {"before", "after"}) {
    const auto& model = std::string(stage) == "before" ? r.model_before : r.model_after;
    // Markers of different load cases may sit at different positions: one file per load case.
    for (const auto& load : problem.load_cases) {
      io::MarkerData one;
      io::MarkerCase mc;
      mc.load_case = load.id;
      for (size_t m = 0; m < markers.size(); ++m) {
        if (markers[m].load_case != load.id) continue;
        one.positions.push_back(markers[m].position);
        mc.measured.push_back(markers[m].displacement);
        mc.model.push_back(model[m]);
      }
      if (one.positions.empty()) continue;
      one.cases.push_back(mc);
      io::write_markers_vtp(out_dir / ("markers_" + load.id + "_" + stage + ".vtp"), one);
    }
  }
}

void run_identify(const IdentifyCommandOptions& options) {
  const io::Progress progress("identify", options.quiet);
  const std::vector<std::string> fixed_outputs{"report.json",   "report.md",
                                               "residuals.svg", "residuals.csv",
                                               "residuals.gp",  "errors_before_after.png",
                                               "model.json"};
  const std::filesystem::path out_dir =
      output_folder(options.output, {options.case_file}, fixed_outputs);
  progress("reading " + options.case_file);
  const io::Case c = io::read_case_file(options.case_file, solve_limits(0));
  std::vector<std::string> outputs = fixed_outputs;
  for (const auto& load : c.problem.load_cases)
    for (const char* stage : {"before", "after"})
      outputs.push_back("markers_" + load.id + "_" + stage + ".vtp");
  io::check_outputs_spare_inputs(case_inputs(c), in_folder(out_dir, outputs));
  if (!c.measurements)
    throw nurbs::InputError(options.case_file +
                            ": no \"measurements\" object; add {\"file\": \"markers.csv\"} "
                            "(see io/markers.hpp for the fields)");
  std::vector<std::string> ids;
  for (const auto& load : c.problem.load_cases) ids.push_back(load.id);
  const io::MeasurementSettings settings = io::read_measurement_settings(
      c.measurements->raw, std::filesystem::path(options.case_file).parent_path(), c.dimension, ids,
      options.case_file + ": measurements");
  const fitting::Measurements data = io::read_markers_csv(settings.file, settings.file_options);
  progress("read " + std::to_string(data.markers.size()) + " markers from " +
           settings.file.string());

  const double tolerance =
      settings.placement_tolerance.value_or(1e-3 * model_diagonal(c.problem.patches));
  const fitting::PlacementResult placed =
      fitting::place_markers(c.problem.patches, data.markers, tolerance);
  std::vector<fitting::Marker> kept;
  std::vector<fitting::MarkerPlacement> placements;
  nlohmann::json dropped = nlohmann::json::array();
  {
    size_t next = 0;
    for (size_t m = 0; m < data.markers.size(); ++m) {
      if (next < placed.outside.size() && placed.outside[next] == static_cast<int>(m)) {
        ++next;
        dropped.push_back({{"row", data.markers[m].row},
                           {"load_case", data.markers[m].load_case},
                           {"distance", placed.placements[m].distance}});
        continue;
      }
      kept.push_back(data.markers[m]);
      placements.push_back(placed.placements[m]);
    }
  }
  if (!placed.outside.empty() && !options.drop_outside) {
    std::string list;
    for (size_t k = 0; k < std::min<size_t>(10, placed.outside.size()); ++k) {
      const auto m = static_cast<size_t>(placed.outside[k]);
      list += "\n  row " + std::to_string(data.markers[m].row) + ": " +
              io::format_number(placed.placements[m].distance, 3) + " m off the model";
    }
    throw nurbs::InputError(
        settings.file.string() + ": " + std::to_string(placed.outside.size()) +
        " marker(s) lie farther than " + io::format_number(tolerance, 3) +
        " m from the model (measurements.placement_tolerance):" + list +
        (placed.outside.size() > 10 ? "\n  ..." : "") +
        "\nfix the data or its units/columns, or pass --drop-outside to leave them out");
  }
  if (!placed.outside.empty())
    progress.warn("dropped " + std::to_string(placed.outside.size()) +
                  " marker(s) off the model (listed in report.json)");

  fitting::IdentifyOptions identify_options = settings.identify;
  identify_options.progress = [&progress](const std::string& s) { progress(s); };
  identify_options.discretization.ladder = io::case_refinement_ladder(c);
  if (options.max_dofs) identify_options.discretization.max_dofs = *options.max_dofs;
  if (options.no_discretization_check) identify_options.discretization.enabled = false;
  const fitting::IdentifyResult r =
      fitting::identify(c.problem, kept, placements, identify_options);

  // Carry it through: recalibrate the spring model against the corrected reference. A failed
  // recalibration is reported, not fatal: the identification itself stands. That includes input
  // errors of the calibration (no density for the masses, prescribed non-zero supports): the case
  // is fine for identification; only the "calibration" object itself is checked strictly above.
  progress("recalibrating the spring model against the corrected reference");
  const fitting::CalibrationSettings calibration_settings =
      parse_calibration(c.calibration, options.case_file).settings;
  std::optional<fitting::Recalibration> recalibration;
  std::string recalibration_error;
  try {
    recalibration = fitting::recalibrate_identified(c.problem, r, calibration_settings);
  } catch (const std::exception& e) {
    recalibration_error = e.what();
    progress.warn("recalibration failed: " + recalibration_error + "; model.json not written");
  }

  nlohmann::json report = io::report_header("identify", ISOSPRING_VERSION, options.case_file);
  report["case"] = io::case_summary(c, c.problem);
  report["data_file"] = settings.file.string();
  report["markers"] = kept.size();
  report["markers_dropped"] = dropped;
  report["placement_tolerance"] = tolerance;
  report["discretization"] = io::discretization_json(r.discretization, r.discretization_allowance);
  report["effects_added"] = r.effects_added;
  for (const auto& p : r.parameters)
    report["parameters"].push_back({{"effect", p.effect},
                                    {"name", p.name},
                                    {"unit", p.unit},
                                    {"value", p.value},
                                    {"standard_error", p.standard_error}});
  for (const auto& p : r.parameters_before)
    report["parameters_before"].push_back({{"effect", p.effect},
                                           {"name", p.name},
                                           {"unit", p.unit},
                                           {"value", p.value},
                                           {"standard_error", p.standard_error}});
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
    for (const auto& t : round.candidates)
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
    report["selection"].push_back(j);
  }
  report["alternatives"] = nlohmann::json::array();
  for (const auto& a : r.alternatives)
    report["alternatives"].push_back({{"replaced", a.replaced},
                                      {"by", a.by},
                                      {"delta_bic", a.delta_bic},
                                      {"swapped", a.swapped}});
  report["selection_rule"] = "F-test, significance " +
                             io::format_number(identify_options.significance) +
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

  io::MarkdownReport md;
  md.heading(1, "isospring identify: " + c.name);
  io::add_case_summary(md, report["case"]);
  md.heading(2, "Data");
  md.paragraph(
      std::to_string(kept.size()) + " markers from `" + settings.file.string() + "`" +
      (dropped.empty() ? std::string(".")
                       : ", " + std::to_string(dropped.size()) + " dropped (farther than " +
                             io::format_number(tolerance, 3) + " m from the model).") +
      " Noise level " + io::format_number(r.noise_estimate, 3) + " m (" +
      (r.noise_given ? "given" : "estimated from neighbouring residual differences") + ").");
  io::add_discretization(md, r.discretization, r.discretization_allowance);
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
    rows.push_back({"nominal model (before)", p.name, io::format_number(p.value),
                    io::format_number(p.standard_error, 3), p.unit});
  for (const auto& p : r.parameters)
    rows.push_back({p.effect, p.name, io::format_number(p.value),
                    io::format_number(p.standard_error, 3), p.unit});
  md.table({"effect", "parameter", "value", "std. error", "unit"}, rows);
  for (const auto& [name, value] : r.derived) md.bullets({name + " = " + io::format_number(value)});
  md.heading(2, "Errors");
  rows.clear();
  rows.push_back({"all", std::to_string(kept.size()), io::format_number(r.before.rms, 4),
                  io::format_number(r.after.rms, 4), io::format_number(r.before.max_norm, 4),
                  io::format_number(r.after.max_norm, 4)});
  for (const auto& lc : r.load_cases)
    rows.push_back({lc.id, std::to_string(lc.markers), io::format_number(lc.before.rms, 4),
                    io::format_number(lc.after.rms, 4), io::format_number(lc.before.max_norm, 4),
                    io::format_number(lc.after.max_norm, 4)});
  md.table({"load case", "markers", "rms before [m]", "rms after [m]", "max \\|r\\| before [m]",
            "max \\|r\\| after [m]"},
           rows);
  md.paragraph(
      "rms: over every component of every marker; max |r|: the longest residual vector, as in "
      "residuals.csv, residuals.svg and the marker .vtp files (report.json also has `max`, the "
      "largest single component).");
  md.paragraph("chi^2 per degree of freedom: " + io::format_number(r.chi2_before, 4) + " before, " +
               io::format_number(r.chi2_after, 4) + " after (1 is the noise level).");
  {
    // The same rms values as bars (gnuplot; a warning and no figure when it is missing).
    std::vector<std::string> labels{"all"};
    std::vector<double> before{r.before.rms}, after{r.after.rms};
    for (const auto& lc : r.load_cases) {
      labels.push_back(lc.id);
      before.push_back(lc.before.rms);
      after.push_back(lc.after.rms);
    }
    io::PlotOptions bars;
    bars.title = "Marker residual rms: nominal model (before) and with the effects (after)";
    bars.ylabel = "rms residual [m]";
    bars.log_y = true;  // the effects often remove orders of magnitude
    if (io::plot_bars_before_after(out_dir / "errors_before_after.png", labels, before, after,
                                   bars))
      md.paragraph("![rms before and after](errors_before_after.png)");
  }
  if (r.holdout_done)
    md.paragraph("Hold-out (fit on every other marker, validate on the rest): validation rms " +
                 io::format_number(r.holdout.validation_before.rms, 4) + " m before, " +
                 io::format_number(r.holdout.validation_after.rms, 4) + " m after.");
  if (!r.load_case_holdout.empty()) {
    rows.clear();
    for (const auto& h : r.load_case_holdout)
      rows.push_back({h.id, std::to_string(h.markers), io::format_number(h.before.rms, 4),
                      io::format_number(h.after.rms, 4), std::to_string(h.local_parameters)});
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
      rows.push_back({t.effect, std::to_string(t.parameters), io::format_number(t.f_statistic, 4),
                      io::format_number(t.p_value, 3), io::format_number(t.delta_bic, 4), t.note});
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
                                io::format_number(a.delta_bic, 3) +
                                ": the same data explained with fewer parameters)"
                          : "cannot be told apart on these data: " + a.replaced + " or " + a.by +
                                " (delta BIC " + io::format_number(a.delta_bic, 3) + ", below 2)");
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
                 io::format_number(rc.corrected.material.youngs_modulus) + " Pa, nu " +
                 io::format_number(rc.corrected.material.poisson_ratio) +
                 ", the physical effects below): %e_rms " + io::format_number(rc.percent_e_rms, 4) +
                 " %, %e_max " + io::format_number(rc.percent_e_max, 4) +
                 " % on the control points (root mean square / largest over the load cases).");
    md.bullets(rc.notes);
  } else {
    md.paragraph("Recalibration failed: " + recalibration_error);
  }
  md.paragraph(
      "Plot: `residuals.svg` (data `residuals.csv`); VTK: `markers_<case>_before.vtp`, "
      "`markers_<case>_after.vtp`.");

  std::filesystem::create_directories(out_dir);
  if (recalibration) {
    const fitting::Recalibration& rc = *recalibration;
    io::SpringModel model;
    model.network = rc.calibration.mesh.network;
    model.units = io::default_model_units();
    model.gravity = rc.gravity;
    const int dim = model.network.dimension;
    for (size_t l = 0; l < rc.corrected.load_cases.size(); ++l) {
      io::ModelLoadCase load;
      load.id = rc.corrected.load_cases[l].id;
      const Eigen::VectorXd& f = rc.particle_loads[l];
      for (Eigen::Index p = 0; p < f.size() / dim; ++p)
        if (!f.segment(p * dim, dim).isZero(0.0)) {
          Eigen::Vector3d force = Eigen::Vector3d::Zero();
          force.head(dim) = f.segment(p * dim, dim);
          load.forces.emplace_back(static_cast<int>(p), force);
        }
      model.load_cases.push_back(std::move(load));
    }
    model.provenance = {{"case", c.name},
                        {"isospring_version", ISOSPRING_VERSION},
                        {"identify",
                         {{"effects_added", r.effects_added},
                          {"reference", "the identified model (corrected reference)"},
                          {"percent_e_rms", rc.percent_e_rms},
                          {"percent_e_max", rc.percent_e_max},
                          {"gamma", rc.calibration.gamma}}}};
    io::write_spring_model_json(out_dir / "model.json", model);
  }
  write_markers(out_dir, c.problem, kept, r);
  write_residual_plot(out_dir, kept, r);
  io::add_warnings(report, md, progress);
  io::write_json_report(out_dir / "report.json", report);
  md.write(out_dir / "report.md");
  progress("rms " + io::format_number(r.before.rms, 3) + " m -> " +
           io::format_number(r.after.rms, 3) + " m; wrote " + (out_dir / "report.json").string());
}

void setup_identify(CLI::App& app) {
  auto options = std::make_shared<IdentifyCommandOptions>();
  CLI::App* cmd = app.add_subcommand(
      "identify", "Fit the model to measured marker displacements and add missing effects");
  cmd->footer(
      "The case file's \"measurements\" object names the marker CSV (header\n"
      "load_case,x,y,z,ux,uy,uz[,sigma] by default; columns and units can be mapped).\n"
      "Fits E (and nu with fit_poisson), then adds effects (gravity, support_compliance,\n"
      "stiffness_gradient, rigid_offset, load_scale, geometric_nonlinearity,\n"
      "rigid_offset_per_load) while an F-test\n"
      "finds them significant (docs/identify.md). Before that, the reference is refined\n"
      "(degree, then elements) until its error at the markers is below a third of the\n"
      "noise, within --max-dofs; beyond the budget the F-tests are widened instead.\n"
      "Recalibrates the spring model against the corrected reference (identified material,\n"
      "gravity, load factors, stiffness gradient; the case's \"calibration\" object applies).\n"
      "Writes OUTDIR/report.json, report.md, model.json, residuals.svg/.csv,\n"
      "markers_<case>_*.vtp.");
  cmd->add_option("CASE", options->case_file, "Case file (.json) with \"measurements\"")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", options->output, "Output folder (created if missing)")->required();
  cmd->add_flag("--drop-outside", options->drop_outside,
                "Leave out markers off the model (listed in the report) instead of failing");
  cmd->add_option("--max-dofs", options->max_dofs,
                  "DOF budget of the discretisation check (default: measurements.max_dofs, "
                  "else 25000)")
      ->check(CLI::Range(1L, 1000000000L));
  cmd->add_flag("--no-discretization-check", options->no_discretization_check,
                "Run the loop on the case's discretisation without checking its error against "
                "the noise");
  cmd->add_flag("-q,--quiet", options->quiet, "No progress lines");
  cmd->callback([options] { run_identify(*options); });
}

}  // namespace
ISOSPRING_REGISTER_COMMAND(60, setup_identify);
}  // namespace isospring::apps
