// run_demo: the pipeline of `isospring demo` (see demo_command.hpp). Each step reuses the
// library the other commands use; this file only composes them.
#include "isospring/workflows/demo_command.hpp"

#include <chrono>
#include <cmath>
#include <optional>

#include "isospring/analysis/post_processing.hpp"
#include "isospring/analysis/static_solver.hpp"
#include "isospring/fitting/calibration.hpp"
#include "isospring/geometry/cad.hpp"
#include "isospring/geometry/measure.hpp"
#include "isospring/io/calibration_outputs.hpp"
#include "isospring/io/calibration_settings.hpp"
#include "isospring/io/case_file.hpp"
#include "isospring/io/export_mjcf.hpp"
#include "isospring/io/export_sofa.hpp"
#include "isospring/io/model_file.hpp"
#include "isospring/io/report.hpp"
#include "isospring/io/vtk_fields.hpp"
#include "isospring/io/vtk_multiblock.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::workflows {
// The use cases read and write io's formats; io's names are used unqualified here.
using namespace isospring::io;
namespace {
namespace fs = std::filesystem;

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// Per-node NMSM error (u_nmsm - u_ref) as a control field on the patches, so ParaView shows it
/// on the geometry.
ControlField node_error_field(const std::string& name, const fitting::SpringMesh& mesh,
                              const std::vector<Eigen::Vector3d>& node_error) {
  ControlField field{name, 3, {}};
  for (const auto& particles : mesh.particle) {
    Eigen::MatrixXd values(3, static_cast<Eigen::Index>(particles.size()));
    for (size_t i = 0; i < particles.size(); ++i)
      values.col(static_cast<Eigen::Index>(i)) = node_error[static_cast<size_t>(particles[i])];
    field.coefficients.push_back(values);
  }
  return field;
}

/// The report's "steps": one entry per pipeline step, its details with its name and run time.
struct StepLog {
  nlohmann::json steps = nlohmann::json::array();
  void done(const std::string& name, double seconds, nlohmann::json details) {
    details["step"] = name;
    details["seconds"] = seconds;
    steps.push_back(details);
  }
};

/// %e_rms and %e_max per load case, as report.json and the model's provenance list them.
nlohmann::json case_summary(const std::vector<fitting::CaseErrors>& cases) {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& e : cases)
    list.push_back({{"id", e.id},
                    {"percent_e_rms", e.control.percent_e_rms},
                    {"percent_e_max", e.control.percent_e_max}});
  return list;
}

/// Steps 1-2. CAD -> NURBS -> refinement: the case file names the part and the discretisation.
Case cad_and_refinement(const fs::path& case_path, const Progress& progress, StepLog& log) {
  const auto t = std::chrono::steady_clock::now();
  Case c = read_case_file(case_path);
  const analysis::Problem& problem = c.problem;
  const double exact_volume = geometry::measure(c.geometry);
  int control_points = 0;
  for (const auto& patch : problem.patches) control_points += patch.num_points();
  progress("1/6 CAD -> NURBS: " + std::to_string(c.geometry.size()) +
           " exact patch(es) from the part, volume " + format_number(exact_volume) + " m^3");
  progress("2/6 refinement: degree " + std::to_string(c.discretization.degree[0]) + ", " +
           std::to_string(problem.patches.front().num_elements()) + " elements, " +
           std::to_string(control_points) + " control points");
  log.done("cad_to_nurbs_and_refinement", seconds_since(t),
           {{"exact_patches", c.geometry.size()},
            {"volume_m3", exact_volume},
            {"refined_volume_m3", geometry::measure(problem.patches)},
            {"control_points", control_points}});
  return c;
}

/// Step 3. IGA reference.
analysis::StaticResult iga_reference(const analysis::Problem& problem, const Progress& progress,
                                     StepLog& log) {
  const auto t = std::chrono::steady_clock::now();
  analysis::StaticResult reference = analysis::solve_static(problem);
  nlohmann::json reference_json = nlohmann::json::array();
  for (const auto& r : reference.load_cases)
    reference_json.push_back({{"id", r.id},
                              {"max_displacement_m", r.max_displacement},
                              {"strain_energy_J", r.strain_energy}});
  progress("3/6 IGA reference: " + std::to_string(reference.dofs) + " DOFs, " +
           std::to_string(reference.load_cases.size()) + " load cases solved");
  log.done("iga_reference", seconds_since(t),
           {{"dofs", reference.dofs}, {"load_cases", reference_json}});
  return reference;
}

/// Step 4. NMSM calibration, settings from the case's "calibration" object, against the
/// reference of step 3 (the calibration would solve the same problem again).
fitting::CalibrationResult nmsm_calibration(const Case& c, const fs::path& case_path,
                                            const analysis::StaticResult& reference,
                                            const Progress& progress, StepLog& log) {
  const auto t = std::chrono::steady_clock::now();
  CalibrationRequest request = read_calibration_settings(c.calibration, case_path.string());
  if (!progress.quiet()) {
    request.settings.progress = [&](const std::string& line) { progress("   " + line); };
    request.settings.iteration = [&](const std::string& stage, int iteration, double cost) {
      progress.update("4/6 " + stage, iteration, cost);
    };
  }
  for (const auto& r : reference.load_cases)
    request.settings.reference_displacements.push_back(r.displacement);
  fitting::CalibrationResult calibration = fitting::calibrate(c.problem, request.settings);
  progress("4/6 NMSM calibration: " + std::to_string(calibration.mesh.network.springs.size()) +
           " springs, " + std::to_string(calibration.parameters) + " stiffness groups, fitted in " +
           format_number(calibration.fit_seconds, 3) + " s");
  for (const auto& warning : calibration.mesh.warnings) progress.warn(warning);
  for (const auto& warning : calibration.warnings) progress.warn(warning);
  for (const auto& e : calibration.fit)
    progress("   fitted  " + e.id + ": %e_rms " + format_number(e.control.percent_e_rms, 3) +
             ", %e_max " + format_number(e.control.percent_e_max, 3));
  for (const auto& e : calibration.holdout)
    progress("   holdout " + e.id + ": %e_rms " + format_number(e.control.percent_e_rms, 3) +
             ", %e_max " + format_number(e.control.percent_e_max, 3));
  log.done("nmsm_calibration", seconds_since(t),
           {{"springs", calibration.mesh.network.springs.size()},
            {"groups", calibration.parameters},
            {"fit_seconds", calibration.fit_seconds},
            {"fit", case_summary(calibration.fit)},
            {"holdout", case_summary(calibration.holdout)}});
  return calibration;
}

/// Step 5. VTK: geometry with displacement and von Mises per load case, NMSM error fields, net,
/// springs; and the calibration's figures (the same as `isospring calibrate` draws), which
/// report.md links. Returns the figures' names.
std::vector<std::string> vtk_and_figures(const analysis::Problem& problem,
                                         const analysis::StaticResult& reference,
                                         const fitting::CalibrationResult& calibration,
                                         const fs::path& out, const Progress& progress,
                                         StepLog& log) {
  const auto t = std::chrono::steady_clock::now();
  VtkScene scene;
  scene.patches = problem.patches;
  for (const auto& r : reference.load_cases) {
    scene.fields.control.push_back(
        control_vector_field("displacement_" + r.id, r.control_displacements));
    const auto* displacements = &r.control_displacements;
    scene.fields.evaluated.push_back(von_mises_field(
        "von_mises_" + r.id, [&problem, displacements](int patch, const nurbs::Param& u) {
          return analysis::evaluate_field(problem, *displacements, patch, u).stress;
        }));
  }
  for (const auto* cases : {&calibration.fit, &calibration.holdout})
    for (const auto& e : *cases)
      scene.fields.control.push_back(
          node_error_field("nmsm_error_" + e.id, calibration.mesh, e.node_error));
  scene.network = calibration.mesh.network;
  const auto vtk_files = write_vtk_scene(out / "result.vtm", scene);
  progress("5/6 VTK: " + (out / "result.vtm").string() + " (" + std::to_string(vtk_files.size()) +
           " files)");
  std::vector<std::string> figures = write_calibration_figures(out, problem, calibration);
  log.done("vtk_and_figures", seconds_since(t),
           {{"files", vtk_files.size()}, {"figures", figures}});
  return figures;
}

/// Step 6. Exports for engines: model.json (with the calibration's loads), MuJoCo and SOFA.
void engine_exports(const Case& c, const fs::path& case_path,
                    const fitting::CalibrationResult& calibration, const fs::path& out,
                    const Progress& progress, StepLog& log) {
  const auto t = std::chrono::steady_clock::now();
  const nlohmann::json provenance = {{"case", case_path.string()},
                                     {"command", "isospring demo"},
                                     {"isospring_version", isospring_version()},
                                     {"fit", case_summary(calibration.fit)},
                                     {"holdout", case_summary(calibration.holdout)}};
  SpringModel model;
  model.network = calibration.mesh.network;
  model.provenance = provenance;
  model.units = default_model_units();
  for (size_t l = 0; l < calibration.particle_loads.size(); ++l)
    model.load_cases.push_back(model_load_case(
        calibration.load_ids[l], calibration.particle_loads[l], model.network.dimension));
  write_spring_model_json(out / "model.json", model);
  MjcfOptions mjcf;
  mjcf.comment = "isospring demo: " + c.name;
  // -z for a solid, in-plane -y for a flat (2D) case, whose particles move in x-y only.
  mjcf.gravity = engine_gravity(model.network, Eigen::Vector3d::Zero(), std::nullopt);
  write_mjcf(out / "model_mujoco.xml", calibration.mesh.network, mjcf);
  SofaOptions sofa;
  sofa.comment = mjcf.comment;
  sofa.gravity = mjcf.gravity;
  write_sofa_scene(out / "model_sofa.scn", calibration.mesh.network, sofa);
  progress("6/6 exports: model.json, model_mujoco.xml (MuJoCo), model_sofa.scn (SOFA)");
  log.done("exports", seconds_since(t),
           {{"files", {"model.json", "model_mujoco.xml", "model_sofa.scn"}}});
}

/// report.md: the steps' times, the NMSM's errors, the warnings and the figures.
void write_demo_markdown(const Case& c, const fs::path& case_path, const StepLog& log, double total,
                         const fitting::CalibrationResult& calibration,
                         const std::vector<std::string>& figures, const fs::path& out,
                         const Progress& progress) {
  MarkdownReport md;
  md.heading(1, "isospring demo: " + c.name);
  md.paragraph("Case `" + case_path.string() + "`. The whole pipeline ran in " +
               format_number(total, 3) + " s.");
  std::vector<std::vector<std::string>> rows;
  for (const auto& s : log.steps)
    rows.push_back({s["step"].get<std::string>(), format_number(s["seconds"].get<double>(), 3)});
  md.table({"step", "seconds"}, rows);
  md.heading(2, "NMSM against the IGA reference");
  rows.clear();
  for (const auto& e : calibration.fit)
    rows.push_back({e.id, "fitted", format_number(e.control.percent_e_rms, 3),
                    format_number(e.control.percent_e_max, 3)});
  for (const auto& e : calibration.holdout)
    rows.push_back({e.id, "held out", format_number(e.control.percent_e_rms, 3),
                    format_number(e.control.percent_e_max, 3)});
  md.table({"load case", "use", "%e_rms", "%e_max"}, rows);
  if (!progress.warnings().empty()) {
    std::vector<std::string> items;
    for (const auto& w : progress.warnings()) items.push_back("Warning: " + w);
    md.bullets(items);
  }
  for (const std::string& figure : figures) md.paragraph("![" + figure + "](" + figure + ")");
  md.paragraph(
      "Open `result.vtm` in ParaView (raise *Nonlinear Subdivision Level* to see the exact "
      "Bezier geometry curved). `model.json` is the calibrated spring model; "
      "`model_mujoco.xml` and `model_sofa.scn` load in MuJoCo and SOFA.");
  md.write(out / "report.md");
}

}  // namespace

std::vector<std::string> demo_output_files() {
  return {"result.vtm",  "model.json", "model_mujoco.xml",     "model_sofa.scn",
          "report.json", "report.md",  "errors_histogram.png", "errors_vs_position.png"};
}

double run_demo(const fs::path& case_path, const fs::path& out, const Progress& progress) {
  const auto start = std::chrono::steady_clock::now();
  nlohmann::json report = report_header("demo", isospring_version(), case_path);
  StepLog log;
  const Case c = cad_and_refinement(case_path, progress, log);
  const analysis::StaticResult reference = iga_reference(c.problem, progress, log);
  const fitting::CalibrationResult calibration =
      nmsm_calibration(c, case_path, reference, progress, log);
  const std::vector<std::string> figures =
      vtk_and_figures(c.problem, reference, calibration, out, progress, log);
  engine_exports(c, case_path, calibration, out, progress, log);

  const double total = seconds_since(start);
  report["case"] = c.name;
  report["steps"] = log.steps;
  report["total_seconds"] = total;
  report["figures"] = figures;
  report["warnings"] = progress.warnings();
  write_json_report(out / "report.json", report);
  write_demo_markdown(c, case_path, log, total, calibration, figures, out, progress);
  return total;
}

}  // namespace isospring::workflows
