// run_export and its report (see export_command.hpp).
#include "isospring/io/export_command.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "isospring/io/atomic_file.hpp"
#include "isospring/io/export_mjcf.hpp"
#include "isospring/io/export_sofa.hpp"
#include "isospring/io/number_list.hpp"
#include "isospring/io/vtk_multiblock.hpp"
#include "isospring/io/vtk_spring_network.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::io {
namespace {
namespace fs = std::filesystem;

/// --format, or the output's extension when it is not given.
std::string format_of(const ExportCommandOptions& options) {
  if (!options.format.empty()) return options.format;
  const std::string ext = fs::path(options.output).extension().string();
  if (ext == ".json") return "json";
  if (ext == ".xml" || ext == ".mjcf") return "mjcf";
  if (ext == ".scn") return "sofa";
  if (ext == ".vtp" || ext == ".vtm") return "vtk";
  throw nurbs::InputError("-o " + options.output +
                          ": cannot tell the format from the extension; add --format "
                          "json|mjcf|sofa|vtk (or use .json, .xml, .scn, .vtp, .vtm)");
}

// --gravity, or the default for the model (engine_gravity: the model's own, else -z in 3D
// and -y for a flat model); a z gravity for a flat model is refused.
Eigen::Vector3d export_gravity(const std::string& text, const SpringModel& model) {
  std::optional<Eigen::Vector3d> given;
  if (!text.empty()) {
    const std::vector<double> g = parse_number_list(text, "--gravity");
    if (g.size() != 3) throw nurbs::InputError("--gravity: give three numbers gx,gy,gz in m/s^2");
    given = Eigen::Vector3d(g[0], g[1], g[2]);
  }
  return engine_gravity(model.network, model.gravity, given);
}

}  // namespace

ExportCommandResult run_export(const ExportCommandOptions& options) {
  ExportCommandResult r;
  r.model = read_model_json(options.input);
  r.format = format_of(options);
  const SpringModel& model = r.model;
  const std::string& format = r.format;
  const fs::path output = options.output;
  const std::string provenance =
      "source " + fs::path(options.input).filename().string() +
      (model.provenance.empty() ? std::string() : "; provenance " + model.provenance.dump());
  if (options.timestep < 0) throw nurbs::InputError("--timestep: must be >= 0 (0 = automatic)");
  if (format == "json") {
    write_spring_model_json(output, model);  // with its gravity and load cases
  } else if (format == "mjcf") {
    MjcfOptions o;
    o.model_name = fs::path(options.input).stem().string();
    o.gravity = export_gravity(options.gravity, model);
    o.timestep = options.timestep;
    o.comment = provenance;
    write_mjcf(output, model.network, o);
  } else if (format == "sofa") {
    SofaOptions o;
    o.gravity = export_gravity(options.gravity, model);
    o.timestep = options.timestep;
    o.comment = provenance;
    write_sofa_scene(output, model.network, o);
  } else if (format == "reduced") {
    ReducedExportOptions o;
    o.modes = options.modes;
    o.timestep = options.timestep > 0.0 ? options.timestep : 1e-3;
    r.reduced = export_reduced_model(model, o, {{"source", options.input}});
    write_file_atomically(output, r.reduced->document.dump() + "\n");
  } else if (output.extension() == ".vtm") {
    VtkScene scene;
    scene.network = model.network;
    write_vtk_scene(output, scene);
  } else {
    write_spring_network_vtp(output, model.network);
  }
  return r;
}

// <stem>.report.json / .md beside the export: what the engine receives (counts, mass, stiffness
// and damping ranges, loads), so a user can check it without opening the file.
void export_report(const ExportCommandResult& r, const ExportCommandOptions& options,
                   nlohmann::json& j, MarkdownReport& md) {
  const std::string& format = r.format;
  const SpringModel& model = r.model;
  const analysis::SpringNetwork& network = model.network;
  const auto fixed = std::count(network.fixed.begin(), network.fixed.end(), true);
  double mass = 0.0;
  for (double m : network.masses) mass += m;
  double k_min = INFINITY, k_max = 0.0, c_min = INFINITY, c_max = 0.0;
  for (const auto& s : network.springs) {
    k_min = std::min(k_min, s.stiffness), k_max = std::max(k_max, s.stiffness);
    c_min = std::min(c_min, s.damping), c_max = std::max(c_max, s.damping);
  }
  j["format"] = format;
  j["particles"] = network.positions.size();
  j["fixed_particles"] = fixed;
  j["springs"] = network.springs.size();
  j["dimension"] = network.dimension;
  j["total_mass"] = mass;
  // A network without springs (particles only) has no ranges: null, "-" in the table.
  const bool any = !network.springs.empty();
  j["stiffness_range"] = any ? nlohmann::json{k_min, k_max} : nlohmann::json();
  j["damping_range"] = any ? nlohmann::json{c_min, c_max} : nlohmann::json();
  const auto range = [any](double lo, double hi) {
    return any ? format_number(lo, 4) + " .. " + format_number(hi, 4) : std::string("-");
  };
  j["load_cases"] = model.load_cases.size();
  j["units"] = model.units;
  if (format == "mjcf" || format == "sofa") {
    const Eigen::Vector3d g = export_gravity(options.gravity, model);
    j["gravity"] = {g.x(), g.y(), g.z()};
    j["timestep"] = options.timestep;
  }
  if (r.reduced) {
    j["timestep"] = r.reduced->document.at("timestep");
    j["modes"] = options.modes;
    j["basis_size"] = r.reduced->basis_size;
    j["reduction_errors"] = r.reduced->document.at("errors");
  }
  md.heading(1, "isospring export: " + options.input + " -> " + options.output);
  md.table({"format", "particles", "fixed", "springs", "total mass [kg]", "stiffness [N/m]",
            "damping [N s/m]"},
           {{format, std::to_string(network.positions.size()), std::to_string(fixed),
             std::to_string(network.springs.size()), format_number(mass), range(k_min, k_max),
             range(c_min, c_max)}});
  if (r.reduced) {
    std::vector<std::vector<std::string>> rows;
    for (const ReducedLoadError& e : r.reduced->errors)
      rows.push_back({e.load, format_number(e.error.static_relative, 3),
                      format_number(e.error.projection_relative, 3),
                      e.error.exact_diverged ? "full network's run diverged"
                                             : format_number(e.error.dynamic_relative, 3),
                      e.error.exact_diverged ? "-" : format_number(e.error.dynamic_max, 3),
                      std::to_string(e.error.steps)});
    md.paragraph("Reduced model: " + std::to_string(r.reduced->basis_size) + " basis vectors (" +
                 std::to_string(options.modes) +
                 " modes + the load shapes); error against the full network from rest under "
                 "each load (docs/reduced_model.md):");
    md.table({"load", "static (relative)", "motion vs linearised network (rms relative)",
              "motion vs full network (rms relative)", "largest [m]", "steps"},
             rows);
  }
}

}  // namespace isospring::io
