// The files of `isospring calibrate` on an immersed case (see calibrate_immersed.hpp).
#include <cmath>

#include "isospring/analysis/immersed_particles.hpp"
#include "isospring/io/atomic_file.hpp"
#include "isospring/io/model_file.hpp"
#include "isospring/io/vtk_spring_network.hpp"
#include "isospring/io/vtk_surface_fields.hpp"
#include "isospring/workflows/calibrate_command.hpp"
#include "isospring/workflows/calibrate_immersed.hpp"
#include "surface_refinement.hpp"

namespace isospring::workflows {
using namespace isospring::io;
namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

void write_errors_csv(const std::filesystem::path& path, const ImmersedCalibrateResult& r,
                      const fitting::CaseErrors& errors) {
  const auto& positions = r.calibration.calibration.mesh.network.positions;
  std::string text = "particle,control_point,x,y,z,ex,ey,ez,error\n";
  for (size_t a = 0; a < positions.size(); ++a) {
    const Eigen::Vector3d& x = positions[a];
    const Eigen::Vector3d& e = errors.node_error[a];
    text += std::to_string(a) + "," + std::to_string(r.calibration.control_point_of_particle[a]);
    for (double v : {x.x(), x.y(), x.z(), e.x(), e.y(), e.z(), e.norm()})
      text += "," + format_exact(v);
    text += "\n";
  }
  write_file_atomically(path, text);
}

// Root mean square of %e_rms, the largest %e_max and every case's errors.
nlohmann::json summary_json(const std::vector<fitting::CaseErrors>& cases) {
  if (cases.empty()) return nullptr;
  double sum = 0.0, worst = 0.0;
  nlohmann::json list = nlohmann::json::array();
  for (const auto& e : cases) {
    sum += e.control.percent_e_rms * e.control.percent_e_rms;
    worst = std::max(worst, e.control.percent_e_max);
    list.push_back(case_errors_json(e));
  }
  return {{"percent_e_rms", std::sqrt(sum / static_cast<double>(cases.size()))},
          {"percent_e_max", worst},
          {"load_cases", list}};
}

SpringModel spring_model(const ImmersedCalibrateResult& r, const nlohmann::json& report) {
  const fitting::CalibrationResult& result = r.calibration.calibration;
  const fitting::CalibrationSettings& settings = r.request.settings;
  SpringModel model;
  model.network = result.mesh.network;
  model.units = default_model_units();
  model.provenance = {{"case", r.c.name},
                      {"isospring_version", isospring_version()},
                      {"path", "immersed"},
                      {"fit",
                       {{"objective", "displacement"},
                        {"percent_e_rms", report["percent_e_rms"]},
                        {"percent_e_max", report["percent_e_max"]},
                        {"groups", result.parameters},
                        {"gamma", result.gamma}}}};
  if (settings.damping_alpha > 0.0)
    model.provenance["damping"] = {{"alpha", settings.damping_alpha}};
  else if (settings.damping_ratio > 0.0)
    model.provenance["damping"] = {{"ratio", settings.damping_ratio}};
  else
    model.provenance["damping"] = nullptr;
  for (size_t l = 0; l < result.particle_loads.size(); ++l)
    model.load_cases.push_back(
        model_load_case(result.load_ids[l], result.particle_loads[l], model.network.dimension));
  return model;
}

nlohmann::json report_json(const ImmersedCalibrateResult& r) {
  const fitting::CalibrationResult& result = r.calibration.calibration;
  const analysis::SpringNetwork& network = result.mesh.network;
  nlohmann::json report = report_header("calibrate", isospring_version(), r.c.file);
  report["path"] = "immersed";
  Eigen::Vector3i n = Eigen::Vector3i::Ones();
  for (int d = 0; d < r.domain.background.param_dim(); ++d)
    n[d] = r.domain.background.knots(d).num_elements();
  report["immersion"] = {
      {"file", r.c.part.string()},          {"degree", r.c.immersion.degree},
      {"cells", {n.x(), n.y(), n.z()}},     {"inside_cells", r.stats.inside_cells},
      {"cut_cells", r.stats.cut_cells},     {"volume", r.quadrature.volume},
      {"volume_opencascade", r.occ.volume}, {"seconds", r.immersion_seconds}};
  report["volumetric"] = volumetric_key(r.c.volumetric);  // of the reference solves
  // The ghost penalty's reach the reference was solved with: the default's, or wider where its
  // stiffness was not positive definite (then a warning says so).
  if (!r.calibration.reference.empty())
    report["ghost_fraction"] = r.calibration.reference.front().ghost_fraction;
  const std::string freedom =
      r.request.settings.per_spring
          ? "one stiffness per spring (" + std::to_string(result.parameters) +
                " parameters), started from the rest-length groups of gamma " +
                format_number(result.gamma)
          : "springs grouped by rest length (gamma " + format_number(result.gamma) + ", " +
                std::to_string(result.parameters) + " groups)";
  report["protocol"] =
      "Displacement objective [S15 5.7] over the fitted load cases, " + freedom +
      ". Particles on the active control points of the background grid, springs on its complete "
      "net cells, masses lumped from the consistent mass over the part, supports on the control "
      "points whose functions reach the held faces; the reference is the immersed IGA solution "
      "(Nitsche supports). Errors on the active control points; field and surface: the spline "
      "fields of both coefficient sets, volume- and area-weighted over the part.";
  report["particles"] = network.positions.size();
  report["held_particles"] = r.calibration.held_particles;
  report["springs"] = network.springs.size();
  report["groups"] = result.parameters;
  report["gamma"] = result.gamma;
  report["iterations"] = result.fit_result.iterations;
  report["termination"] = result.fit_result.message;
  const nlohmann::json fitted = summary_json(result.fit);
  report["percent_e_rms"] = fitted["percent_e_rms"];
  report["percent_e_max"] = fitted["percent_e_max"];
  report["fit"] = fitted;
  report["holdout"] = summary_json(result.holdout);
  report["worst_fitted_percent_e_rms"] = r.worst_fitted;
  report["worst_holdout_percent_e_rms"] =
      result.holdout.empty() ? nlohmann::json() : nlohmann::json(r.worst_holdout);
  report["worst_percent_e_rms"] = r.worst;
  report["seconds"] = {{"immersion", r.immersion_seconds},
                       {"assembly", r.calibration.assembly_seconds},
                       {"reference_solves", result.reference_seconds},
                       {"fit", result.fit_seconds}};
  report["not_computed"] =
      "matrix approach and acceleration-objective baselines (body-fitted models only)";
  return report;
}

MarkdownReport report_markdown(const ImmersedCalibrateResult& r, const nlohmann::json& report) {
  const fitting::CalibrationResult& result = r.calibration.calibration;
  MarkdownReport md;
  md.heading(1, "isospring calibrate (immersed): " + r.c.name);
  md.paragraph("Part " + r.c.part.filename().string() + " immersed in a degree-" +
               std::to_string(r.c.immersion.degree) +
               " grid: " + std::to_string(r.stats.inside_cells) + " inside and " +
               std::to_string(r.stats.cut_cells) + " cut cells; " +
               std::to_string(result.mesh.network.positions.size()) + " particles (" +
               std::to_string(r.calibration.held_particles) + " held), " +
               std::to_string(result.mesh.network.springs.size()) +
               " springs. Reference solves: " + volumetric_sentence(r.c.volumetric) + ".");
  md.heading(2, "Protocol");
  md.paragraph(report["protocol"].get<std::string>());
  md.heading(2, "Errors");
  md.paragraph("Worst %e_rms: " + format_number(r.worst_fitted, 4) + " over the fitted cases, " +
               (result.holdout.empty()
                    ? std::string("no held-out cases")
                    : format_number(r.worst_holdout, 4) + " over the held-out cases (not fitted)") +
               ".");
  std::vector<std::vector<std::string>> rows;
  for (const auto* cases : {&result.fit, &result.holdout})
    for (const auto& e : *cases)
      rows.push_back({e.id, cases == &result.fit ? "fitted" : "held out",
                      format_number(e.control.percent_e_rms, 4),
                      format_number(e.control.percent_e_max, 4),
                      format_number(e.field.percent_e_rms, 4),
                      format_number(e.surface.percent_e_rms, 4), format_number(e.control.o_max)});
  md.table({"load case", "role", "%e_rms", "%e_max", "field %e_rms", "surface %e_rms", "o_max [m]"},
           rows);
  md.paragraph(
      "ParaView: `result.vtp` shows the part with `reference_<id>` (the immersed IGA solution) and "
      "`springs_<id>` (the spring model's displacements as spline coefficients) per case; "
      "`springs.vtp` the springs with `error_<id>`. `isospring export model.json` converts the "
      "model to MuJoCo, SOFA, VTK or JSON.");
  return md;
}

// result.vtp: the part's surface with both displacement fields of every measured case.
void write_surface(const std::filesystem::path& path, const ImmersedCalibrateResult& r) {
  const geometry::CadTriangulation surface = detail::immersed_part_surface(r.c.part, r.domain);
  const fitting::ImmersedCalibrationResult& cal = r.calibration;
  std::vector<SurfacePointField> fields;
  for (size_t c = 0; c < cal.reference.size(); ++c) {
    if (cal.model_control_displacements[c].empty()) continue;  // neither fitted nor held out
    const std::string& id = cal.calibration.load_ids[c];
    fields.push_back({"reference_" + id,
                      analysis::evaluate_immersed_field(
                          r.domain, cal.reference[c].control_displacements, surface.points),
                      {}});
    fields.push_back({"springs_" + id,
                      analysis::evaluate_immersed_field(
                          r.domain, cal.model_control_displacements[c], surface.points),
                      {}});
  }
  write_surface_fields_vtp(path, surface, fields);
}

}  // namespace

nlohmann::json write_calibrate_immersed_outputs(const std::filesystem::path& out_dir,
                                                const ImmersedCalibrateResult& r,
                                                std::chrono::steady_clock::time_point start) {
  const fitting::CalibrationResult& result = r.calibration.calibration;
  nlohmann::json report = report_json(r);
  std::filesystem::create_directories(out_dir);
  // The model first: its writer refuses an inconsistent network.
  write_spring_model_json(out_dir / "model.json", spring_model(r, report));
  std::vector<PointVectors> vectors;
  for (const auto* cases : {&result.fit, &result.holdout})
    for (const auto& e : *cases) {
      write_errors_csv(out_dir / (e.id + "_errors.csv"), r, e);
      vectors.push_back({"error_" + e.id, e.node_error});
    }
  write_spring_network_vtp(out_dir / "springs.vtp", result.mesh.network, vectors);
  write_surface(out_dir / "result.vtp", r);
  report["vtk_file"] = "result.vtp";
  MarkdownReport md = report_markdown(r, report);
  report["warnings"] = nlohmann::json::array();
  for (const auto& w : result.mesh.warnings) report["warnings"].push_back(w);
  for (const auto& w : result.warnings) report["warnings"].push_back(w);
  for (const auto& w : r.domain.warnings) report["warnings"].push_back(w);
  if (!report["warnings"].empty()) {
    std::vector<std::string> items;
    for (const auto& w : report["warnings"]) items.push_back("Warning: " + w.get<std::string>());
    md.bullets(items);
  }
  report["total_seconds"] = seconds_since(start);
  write_json_report(out_dir / "report.json", report);
  md.write(out_dir / "report.md");
  return report;
}

}  // namespace isospring::workflows
