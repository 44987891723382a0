// run_export and its report (see export_command.hpp); the formats are the table of
// export_formats.cpp.
#include "isospring/workflows/export_command.hpp"

#include <algorithm>
#include <cmath>

#include "isospring/nurbs/error.hpp"
#include "isospring/workflows/export_formats.hpp"

namespace isospring::workflows {
// The use cases read and write io's formats; io's names are used unqualified here.
using namespace isospring::io;

ExportCommandResult run_export(const ExportCommandOptions& options) {
  ExportCommandResult r;
  r.model = read_model_json(options.input);
  const ExportFormat& format = export_format_of(options);
  r.format = format.name;
  if (options.timestep < 0) throw nurbs::InputError("--timestep: must be >= 0 (0 = automatic)");
  format.write(options, r);
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
  if (export_format(format).engine_scene) {
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

}  // namespace isospring::workflows
