// `isospring calibrate CASE.json -o OUTDIR`: the NMSM of a case, calibrated against the IGA
// reference with the displacement objective (settings: the case's "calibration" object,
// docs/calibration.md). Writes report.json, report.md, model.json, springs.vtp,
// <load-case>_errors.csv, result.vtm (ParaView) and the error figures (calibration_outputs.hpp).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <memory>
#include <optional>

#include "calibration_outputs.hpp"
#include "calibration_settings.hpp"
#include "cli_util.hpp"
#include "command.hpp"
#include "isospring/analysis/dof_map.hpp"
#include "isospring/analysis/static_solver.hpp"
#include "isospring/fitting/acceleration_fit.hpp"
#include "isospring/fitting/calibration.hpp"
#include "isospring/fitting/generalising_calibration.hpp"
#include "isospring/fitting/load_suite.hpp"
#include "isospring/io/atomic_file.hpp"
#include "isospring/io/case_file.hpp"
#include "isospring/io/model_file.hpp"
#include "isospring/io/output_guard.hpp"
#include "isospring/io/report.hpp"
#include "isospring/io/report_case.hpp"
#include "isospring/io/vtk_spring_network.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::apps {
namespace {

struct CalibrateOptions {
  std::string case_file;
  std::string output;
  bool quiet = false;
};

nlohmann::json metrics_json(const fitting::CaseErrors& e) {
  return {{"id", e.id},
          {"percent_e_rms", e.control.percent_e_rms},
          {"percent_e_max", e.control.percent_e_max},
          {"o_max", e.control.o_max},
          {"field_percent_e_rms", e.field.percent_e_rms},
          {"field_percent_e_max", e.field.percent_e_max},
          {"surface_percent_e_rms", e.surface.percent_e_rms},
          {"surface_percent_e_max", e.surface.percent_e_max}};
}

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
  for (const auto& e : cases) out["load_cases"].push_back(metrics_json(e));
  return out;
}

std::string protocol_text(const fitting::CalibrationSettings& s,
                          const fitting::CalibrationResult& r) {
  std::string text = "Displacement objective [S15 5.7] summed over the fitted load cases; ";
  text += s.per_spring && s.prior_weight > 0.0
              ? "one stiffness per spring (" + std::to_string(r.parameters) +
                    " parameters, L-BFGS, log k pulled towards the gamma " +
                    io::format_number(r.gamma) + " grouped optimum with weight " +
                    io::format_number(s.prior_weight) + ")"
          : s.per_spring ? "one stiffness per spring (" + std::to_string(r.parameters) +
                               " parameters, regularisation weight " +
                               io::format_number(s.regularization) + ")"
                         : "springs grouped by rest length, gamma " + io::format_number(r.gamma) +
                               " (" + std::to_string(r.parameters) + " groups)";
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

void write_errors_csv(const std::filesystem::path& path, const analysis::DofMap& dofs,
                      const fitting::CaseErrors& errors) {
  std::string text = "node,x,y,z,ex,ey,ez,error\n";
  for (int a = 0; a < dofs.num_nodes(); ++a) {
    const Eigen::Vector3d& x = dofs.node_positions()[a];
    const Eigen::Vector3d& e = errors.node_error[a];
    text += std::to_string(a);
    for (double v : {x.x(), x.y(), x.z(), e.x(), e.y(), e.z(), e.norm()})
      text += "," + io::format_exact(v);
    text += "\n";
  }
  io::write_file_atomically(path, text);
}

void run_calibrate(const CalibrateOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const io::Progress progress("calibrate", options.quiet);
  const std::filesystem::path out_dir =
      output_folder(options.output, {options.case_file},
                    {"report.json", "report.md", "model.json", "springs.vtp", "result.vtm",
                     "errors_histogram.png", "errors_vs_position.png"});

  progress("reading " + options.case_file);
  io::Case c = io::read_case_file(options.case_file, solve_limits(0));
  std::vector<std::string> csv_names;
  for (const auto& load : c.problem.load_cases) csv_names.push_back(load.id + "_errors.csv");
  io::check_outputs_spare_inputs(case_inputs(c), in_folder(out_dir, csv_names));
  CalibrationRequest request = parse_calibration(c.calibration, options.case_file);
  fitting::CalibrationSettings& settings = request.settings;
  settings.matrix_approach = request.matrix_approach;
  if (!options.quiet) {
    settings.progress = [&progress](const std::string& line) { progress(line); };
    settings.iteration = [&progress](const std::string& stage, int iteration, double cost) {
      progress.update(stage, iteration, cost);
    };
  }

  // The load suite (issue 14): its training cases are fitted beside the case's own, its
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
                                io::format_number(worst, 3) + ") exceeds target_percent_e_rms " +
                                io::format_number(request.target_percent_e_rms, 3) +
                                ": the spring model does not reach the reference on every load");
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
  const analysis::SpringNetwork& network = result.mesh.network;
  for (const auto& warning : result.mesh.warnings) progress.warn(warning);
  for (const auto& warning : result.warnings) progress.warn(warning);

  nlohmann::json report = io::report_header("calibrate", ISOSPRING_VERSION, options.case_file);
  report["case"] = io::case_summary(c, c.problem);
  report["protocol"] = protocol_text(settings, result);
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
  for (const auto& entry : result.sweep)
    report["sweep"].push_back(
        {{"gamma", entry.gamma}, {"groups", entry.groups}, {"percent_e_rms", entry.percent_e_rms}});
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

  // Outputs: the model first (its writer refuses an inconsistent network), then the tables.
  std::filesystem::create_directories(out_dir);
  nlohmann::json provenance = {{"case", c.name},
                               {"isospring_version", ISOSPRING_VERSION},
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
  io::SpringModel model;
  model.network = network;
  model.provenance = provenance;
  model.units = io::default_model_units();
  for (size_t l = 0; l < result.particle_loads.size(); ++l)
    model.load_cases.push_back(
        io::model_load_case(result.load_ids[l], result.particle_loads[l], network.dimension));
  io::write_spring_model_json(out_dir / "model.json", model);
  const analysis::DofMap dofs(c.problem);
  std::vector<io::PointVectors> vectors;
  for (const auto* cases : {&result.fit, &result.holdout})
    for (const auto& e : *cases) {
      const std::string csv = e.id + "_errors.csv";
      write_errors_csv(out_dir / csv, dofs, e);
      // Error per particle (a merged particle shows the last of its nodes; they agree in u_nmsm).
      const std::vector<int> particle = fitting::particle_of_node(c.problem, result.mesh);
      io::PointVectors v{"error_" + e.id, std::vector<Eigen::Vector3d>(network.positions.size(),
                                                                       Eigen::Vector3d::Zero())};
      for (size_t a = 0; a < particle.size(); ++a) v.values[particle[a]] = e.node_error[a];
      vectors.push_back(std::move(v));
    }
  io::write_spring_network_vtp(out_dir / "springs.vtp", network, vectors);
  // The reference again for the viewer fields (the calibration keeps only the errors): the same
  // deterministic solve, so model = reference + error is the fitted model's response.
  std::vector<std::vector<std::vector<Eigen::Vector3d>>> reference;
  for (const auto& lc : analysis::solve_static(c.problem).load_cases)
    reference.push_back(lc.control_displacements);
  const CalibrationOutputs outputs =
      write_calibration_outputs(out_dir, c.problem, result, reference);
  report["vtk_file"] = "result.vtm";
  report["figures"] = outputs.figures;

  io::MarkdownReport md;
  md.heading(1, "isospring calibrate: " + c.name);
  io::add_case_summary(md, report["case"]);
  md.heading(2, "Protocol");
  md.paragraph(report["protocol"].get<std::string>());
  md.heading(2, "Errors");
  md.paragraph("Worst %e_rms: " + io::format_number(worst_fitted, 4) + " over the fitted cases, " +
               (result.holdout.empty()
                    ? std::string("no held-out cases")
                    : io::format_number(worst_holdout, 4) + " over the held-out cases") +
               (request.target_percent_e_rms > 0.0
                    ? "; target " + io::format_number(request.target_percent_e_rms, 4) +
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
      rows.push_back({e.id, cases == &result.fit ? "fitted" : "held out",
                      io::format_number(e.control.percent_e_rms, 4),
                      io::format_number(e.control.percent_e_max, 4),
                      io::format_number(e.field.percent_e_rms, 4),
                      io::format_number(e.surface.percent_e_rms, 4),
                      io::format_number(e.surface.percent_e_max, 4), "`" + e.id + "_errors.csv`"});
  md.table({"load case", "role", "%e_rms", "%e_max", "field %e_rms", "surface %e_rms",
            "surface %e_max", "errors"},
           rows);
  md.paragraph(
      "%e_rms / %e_max on the control points [S15 4.20-4.21]; field: the NURBS displacement "
      "fields of both models sampled over the whole parameter domain; surface: sampled on the "
      "boundary faces of volume patches without interfaces, seams and collapsed sides (in 2D "
      "the membrane is the surface: the field values), what a viewer or a marker sees.");
  md.paragraph(std::to_string(network.positions.size()) + " particles, " +
               std::to_string(network.springs.size()) + " springs, " +
               std::to_string(result.parameters) + " stiffness parameters; " +
               std::to_string(result.fit_result.iterations) + " iterations, final cost " +
               io::format_number(result.fit_result.cost) + ", fit " +
               io::format_number(result.fit_seconds, 3) + " s.");
  if (!result.matrix.empty()) {
    md.heading(2, "Matrix approach (Frobenius) on the same springs");
    std::vector<std::vector<std::string>> mrows;
    for (const auto& m : result.matrix) {
      const nlohmann::json errors = m.solved ? summary_json(m.fit_cases) : nlohmann::json();
      auto cell = [&](const char* key) {
        return errors.is_null() ? std::string("singular")
                                : io::format_number(errors[key].get<double>(), 4);
      };
      mrows.push_back({m.method, io::format_number(m.fit.relative_residual, 4),
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
                 : io::format_number(a[part][key].get<double>(), 4);
    };
    md.table({"groups", "rel. residual", "springs at k = 0", "%e_rms (fitted)", "%e_max (fitted)",
              "%e_rms (held out)"},
             {{std::to_string(acceleration->fit.group_stiffness.size()),
               io::format_number(acceleration->fit.relative_residual, 4),
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
      srows.push_back({io::format_number(entry.gamma), std::to_string(entry.groups),
                       io::format_number(entry.percent_e_rms, 4)});
    md.table({"gamma", "groups", "%e_rms (fitted cases)"}, srows);
  }
  md.heading(2, "Outputs");
  md.paragraph("ParaView: `result.vtm` (geometry and control net with `reference_<id>`, " +
               std::string("`model_<id>` and `error_<id>` (model - reference) per load case; ") +
               "springs with `model_<id>` and `error_<id>` per particle). `model.json`: the " +
               "calibrated model for `isospring export` and `isospring simulate`.");
  for (const std::string& figure : outputs.figures)
    md.paragraph("![" + figure + "](" + figure + ")");
  report["total_seconds"] =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  io::write_json_report(out_dir / "report.json", report);
  md.write(out_dir / "report.md");
  progress("%e_rms " + io::format_number(report["percent_e_rms"].get<double>(), 4) + " (fitted)" +
           (result.holdout.empty()
                ? std::string()
                : ", " + io::format_number(report["holdout"]["percent_e_rms"].get<double>(), 4) +
                      " (held out)") +
           "; wrote " + out_dir.string());
}

void setup_calibrate(CLI::App& app) {
  auto options = std::make_shared<CalibrateOptions>();
  CLI::App* cmd = app.add_subcommand(
      "calibrate",
      "Build the NURBS mass-spring model of a case and calibrate its stiffnesses "
      "against the isogeometric reference");
  cmd->footer(
      "Settings: the case file's \"calibration\" object (docs/calibration.md).\n"
      "Writes OUTDIR/report.json (springs, groups, %e_rms/%e_max of the fitted and held-out load\n"
      "cases, iterations, final cost, fit time, matrix-approach comparison), OUTDIR/report.md,\n"
      "OUTDIR/model.json (the calibrated spring model), OUTDIR/springs.vtp (springs with the\n"
      "error fields), OUTDIR/<load-case>_errors.csv (error per control point), OUTDIR/result.vtm\n"
      "(ParaView: geometry, control net and springs with reference_<id>, model_<id>, error_<id>)\n"
      "and OUTDIR/errors_histogram.png, OUTDIR/errors_vs_position.png (need gnuplot).\n"
      "Exit status 3 when the fit does not converge.");
  cmd->add_option("CASE", options->case_file, "Case file (.json)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", options->output, "Output folder (created if missing)")->required();
  cmd->add_flag("-q,--quiet", options->quiet, "No progress lines on stderr");
  cmd->callback([options] { run_calibrate(*options); });
}

}  // namespace
ISOSPRING_REGISTER_COMMAND(50, setup_calibrate);
}  // namespace isospring::apps
