// run_analyze_immersed and its outputs (see analyze_immersed.hpp).
#include "isospring/workflows/analyze_immersed.hpp"

#include <algorithm>

#include "isospring/analysis/elasticity.hpp"
#include "isospring/io/vtk_immersed_cells.hpp"
#include "isospring/io/vtk_surface_fields.hpp"
#include "surface_refinement.hpp"

namespace isospring::workflows {
using namespace isospring::io;
namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

/// The projector on a support's held components at a point of outward normal n.
Eigen::Matrix3d held(const analysis::ImmersedSupport& s, const Eigen::Vector3d& n) {
  if (s.symmetry) return n * n.transpose();
  Eigen::Matrix3d p = Eigen::Matrix3d::Zero();
  for (int c = 0; c < 3; ++c) p(c, c) = s.fixed[static_cast<size_t>(c)] ? 1.0 : 0.0;
  return p;
}

Eigen::Vector3d support_traction(const ImmersedAnalysis& a, const analysis::ImmersedOptions& o,
                                 const analysis::ImmersedResult& result) {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  for (const geometry::BoundaryPoint& b : a.domain.boundary)
    for (const analysis::ImmersedSupport& s : o.supports) {
      if (s.face != b.face) continue;
      const Eigen::Matrix3d sigma = analysis::immersed_stress(a.domain, result, o, b.point);
      force += b.weight * (held(s, b.normal) * (sigma * b.normal));
    }
  return force;
}

Eigen::Vector3d applied_force(const geometry::ImmersedDomain& domain,
                              const analysis::ImmersedOptions& o) {
  double volume = 0;
  for (const geometry::ImmersedCell& cell : domain.cells)
    for (double w : cell.weights) volume += w;
  Eigen::Vector3d force = volume * (o.body_force + o.material.density * o.gravity);
  for (const geometry::BoundaryPoint& b : domain.boundary) {
    for (const analysis::ImmersedTraction& t : o.tractions)
      if (t.face == b.face) force += b.weight * t.value;
    for (const analysis::ImmersedPressure& p : o.pressures)
      if (p.face == b.face) force -= b.weight * p.value * b.normal;
  }
  return force;
}

void evaluate_surface(const ImmersedAnalysis& a, const analysis::ImmersedOptions& o,
                      ImmersedLoadCaseResult& lc) {
  for (const Eigen::Vector3d& x : a.surface.points) {
    const Eigen::Vector3d u = analysis::evaluate_immersed(a.domain, lc.result, x).displacement;
    const double vm = analysis::von_mises(analysis::immersed_stress(a.domain, lc.result, o, x));
    lc.surface_displacement.push_back(u);
    lc.surface_von_mises.push_back(vm);
    lc.max_displacement = std::max(lc.max_displacement, u.norm());
    lc.max_von_mises = std::max(lc.max_von_mises, vm);
  }
}

nlohmann::json vec(const Eigen::Vector3d& v) {
  return {v.x(), v.y(), v.z()};
}

nlohmann::json measures_json(const geometry::SolidMeasures& m) {
  return {{"volume", m.volume}, {"area", m.area}, {"centroid", vec(m.centroid)}};
}

}  // namespace

ImmersedAnalysis run_analyze_immersed(const ImmersedCase& c, analysis::SolverOptions::Method method,
                                      const Progress& progress) {
  ImmersedAnalysis a;
  a.c = c;
  progress("immersing " + c.part.filename().string() + " (degree " +
           std::to_string(c.immersion.degree) + ")");
  auto t = std::chrono::steady_clock::now();
  a.domain = geometry::immerse_solid(*c.cad, c.immersion, &a.stats);
  a.immersion_seconds = seconds_since(t);
  a.occ = geometry::measure_solid(*c.cad);
  a.quadrature = geometry::measure_quadrature(a.domain);
  for (const std::string& w : a.domain.warnings) progress.warn(w);
  progress(std::to_string(a.stats.inside_cells) + " inside and " +
           std::to_string(a.stats.cut_cells) + " cut cells in " +
           format_number(a.immersion_seconds, 3) + " s; volume " +
           format_number(a.quadrature.volume) + " m^3 (OpenCascade " + format_number(a.occ.volume) +
           ")");
  t = std::chrono::steady_clock::now();
  a.surface = detail::immersed_part_surface(c.part, a.domain);
  a.surface_seconds = seconds_since(t);
  for (const ImmersedLoadCase& load : c.load_cases) {
    ImmersedLoadCaseResult lc;
    lc.id = load.id;
    analysis::ImmersedOptions o = immersed_options(c, load);
    o.method = method;
    lc.result = analysis::solve_immersed(a.domain, o);
    // The stabilisation the solve needed (solve_immersed widens it where the stiffness was not
    // positive definite); the reactions and stresses below use the same.
    o.ghost_fraction = lc.result.ghost_fraction;
    for (const std::string& w : lc.result.warnings) progress.warn("load case " + lc.id + ": " + w);
    lc.reaction = analysis::immersed_reaction(a.domain, lc.result, o);
    lc.support_traction = support_traction(a, o, lc.result);
    lc.applied_load = applied_force(a.domain, o);
    t = std::chrono::steady_clock::now();
    evaluate_surface(a, o, lc);
    a.surface_seconds += seconds_since(t);
    progress("load case " + lc.id + ": " + std::to_string(lc.result.dofs) +
             " DOFs, max |u| = " + format_number(lc.max_displacement) + " m");
    a.load_cases.push_back(std::move(lc));
  }
  return a;
}

namespace {

// The grid's axes in words, for the report.
std::string frame_sentence(const ImmersedCase& c) {
  if (c.frame == "file") return "the file's axes";
  const Eigen::Matrix3d& f = c.immersion.frame;
  std::string text =
      c.frame == "principal" ? "the part's principal axes of inertia" : "the case's axes";
  for (int k = 0; k < 3; ++k)
    text += std::string(k ? ", " : " (") + "xyz"[k] + " = [" + format_number(f(0, k), 6) + ", " +
            format_number(f(1, k), 6) + ", " + format_number(f(2, k), 6) + "]";
  text += ")";
  if (!c.frame_note.empty()) text += "; " + c.frame_note;
  return text;
}

}  // namespace

nlohmann::json write_immersed_outputs(const ImmersedAnalysis& a,
                                      const std::filesystem::path& out_dir,
                                      const Progress& progress,
                                      std::chrono::steady_clock::time_point start) {
  const ImmersedCase& c = a.c;
  nlohmann::json report = report_header("analyze", isospring_version(), c.file.string());
  report["path"] = "immersed";
  report["path_reason"] =
      "the case's geometry is {\"type\": \"immersed\"}: the solid's exact B-rep embedded in a "
      "degree-" +
      std::to_string(c.immersion.degree) +
      " B-spline background grid, supports imposed by Nitsche's method on its faces";
  Eigen::Vector3i n = Eigen::Vector3i::Ones();
  for (int d = 0; d < a.domain.background.param_dim(); ++d)
    n[d] = a.domain.background.knots(d).num_elements();
  report["immersion"] = {{"file", c.part.string()},
                         {"solid", c.solid},
                         {"degree", c.immersion.degree},
                         {"cells", {n.x(), n.y(), n.z()}},
                         {"inside_cells", a.stats.inside_cells},
                         {"cut_cells", a.stats.cut_cells},
                         {"seconds", a.immersion_seconds},
                         {"warnings", a.domain.warnings}};
  // The grid's axes: the file's, the part's principal axes of inertia, or the case's own.
  const Eigen::Matrix3d& f = a.domain.frame;
  report["immersion"]["frame"] = c.frame;
  report["immersion"]["frame_axes"] = {
      {f(0, 0), f(1, 0), f(2, 0)}, {f(0, 1), f(1, 1), f(2, 1)}, {f(0, 2), f(1, 2), f(2, 2)}};
  if (!c.frame_note.empty()) report["immersion"]["frame_note"] = c.frame_note;
  report["measures"] = {
      {"opencascade", measures_json(a.occ)},
      {"quadrature", measures_json(a.quadrature)},
      {"volume_relative_error", std::abs(a.quadrature.volume - a.occ.volume) / a.occ.volume}};
  report["material"] = {{"E", c.material.youngs_modulus},
                        {"nu", c.material.poisson_ratio},
                        {"density", c.material.density}};
  report["volumetric"] = volumetric_key(c.volumetric);
  MarkdownReport md;
  md.heading(1, "isospring analyze (immersed): " + c.name);
  md.paragraph("Immersed path: " + report["path_reason"].get<std::string>() + ". Part volume " +
               format_number(a.quadrature.volume) + " m^3 from the quadrature, " +
               format_number(a.occ.volume) + " m^3 from OpenCascade; " +
               std::to_string(a.stats.inside_cells) + " inside and " +
               std::to_string(a.stats.cut_cells) + " cut cells, immersed in " +
               format_number(a.immersion_seconds, 3) + " s, the grid along " + frame_sentence(c) +
               ". Volumetric strain: " + volumetric_sentence(c.volumetric) + ".");
  std::vector<SurfacePointField> fields;
  std::vector<std::vector<std::string>> rows;
  for (const ImmersedLoadCaseResult& lc : a.load_cases) {
    const analysis::ImmersedResult& r = lc.result;
    report["dofs"] = r.dofs;
    report["load_cases"].push_back({{"id", lc.id},
                                    {"dofs", r.dofs},
                                    {"strain_energy", r.strain_energy},
                                    {"max_displacement", lc.max_displacement},
                                    {"max_von_mises", lc.max_von_mises},
                                    {"reaction_sum", vec(lc.reaction)},
                                    {"support_traction_sum", vec(lc.support_traction)},
                                    {"applied_load", vec(lc.applied_load)},
                                    {"assembly_seconds", r.assembly_seconds},
                                    {"solve_seconds", r.solve_seconds},
                                    {"iterations", r.iterations},
                                    {"max_nitsche_penalty", r.max_nitsche_penalty},
                                    {"ghost_faces", r.ghost_faces},
                                    {"ghost_fraction", r.ghost_fraction}});
    fields.push_back({"displacement_" + lc.id, lc.surface_displacement, {}});
    fields.push_back({"von_mises_" + lc.id, {}, lc.surface_von_mises});
    rows.push_back({lc.id, std::to_string(r.dofs), format_number(lc.max_displacement),
                    format_number(r.strain_energy),
                    "(" + format_number(lc.reaction.x()) + ", " + format_number(lc.reaction.y()) +
                        ", " + format_number(lc.reaction.z()) + ")",
                    format_number(r.assembly_seconds + r.solve_seconds, 3)});
  }
  write_surface_fields_vtp(out_dir / "result.vtp", a.surface, fields);
  report["vtk_file"] = "result.vtp";
  if (c.write_cells) {  // the grid the part is embedded in, for those who want to see it
    write_immersed_cells_vtu(out_dir / "cells.vtu", a.domain);
    report["cells_file"] = "cells.vtu";
  }
  report["surface"] = {{"points", a.surface.points.size()},
                       {"triangles", a.surface.triangles.size()},
                       {"seconds", a.surface_seconds}};
  report["total_seconds"] = seconds_since(start);
  md.heading(2, "Results");
  md.table({"load case", "DOFs", "max abs(u) [m]", "strain energy [J]", "reaction [N]",
            "assembly + solve [s]"},
           rows);
  md.paragraph(
      "Reactions are the consistent (weak) reactions of the supports "
      "(analysis::immersed_reaction); "
      "they balance the applied loads up to the ghost penalty's share. ParaView: open `result.vtp` "
      "(the "
      "part's triangulation) with `displacement_<id>` and `von_mises_<id>` per load case.");
  add_warnings(report, md, progress);
  write_json_report(out_dir / "report.json", report);
  md.write(out_dir / "report.md");
  progress("wrote " + (out_dir / "report.json").string() + ", report.md and result.vtp");
  return report;
}

}  // namespace isospring::workflows
