// `isospring export MODEL.json -o OUT [--format json|mjcf|sofa|vtk|reduced]`: a calibrated spring
// model (model.json) for real-time engines and viewers: MuJoCo MJCF, a SOFA scene, VTK poly data,
// a validated, normalised model.json, or its reduced (modal + load shapes) model for haptic rates
// (docs/reduced_model.md).
#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>
#include <optional>

#include "cli_util.hpp"
#include "command.hpp"
#include "file_report.hpp"
#include "isospring/io/atomic_file.hpp"
#include "isospring/io/export_mjcf.hpp"
#include "isospring/io/export_reduced.hpp"
#include "isospring/io/export_sofa.hpp"
#include "isospring/io/model_file.hpp"
#include "isospring/io/vtk_multiblock.hpp"
#include "isospring/io/vtk_spring_network.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::apps {
namespace {
namespace fs = std::filesystem;

struct ExportOptions {
  std::string input, output, format, gravity;  // gravity: empty = io::engine_gravity default
  double timestep = 0.0;
  int modes = 32;  // reduced
  bool quiet = false;
};

/// --format, or the output's extension when it is not given.
std::string format_of(const ExportOptions& options) {
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

// --gravity, or the default for the model (io::engine_gravity: the model's own, else -z in 3D
// and -y for a flat model); a z gravity for a flat model is refused.
Eigen::Vector3d export_gravity(const std::string& text, const io::SpringModel& model) {
  std::optional<Eigen::Vector3d> given;
  if (!text.empty()) {
    const std::vector<double> g = parse_number_list(text, "--gravity");
    if (g.size() != 3) throw nurbs::InputError("--gravity: give three numbers gx,gy,gz in m/s^2");
    given = Eigen::Vector3d(g[0], g[1], g[2]);
  }
  return io::engine_gravity(model.network, model.gravity, given);
}

// <stem>.report.json / .md beside the export: what the engine receives (counts, mass, stiffness
// and damping ranges, loads), so a user can check it without opening the file.
void write_export_report(const ExportOptions& options, const std::string& format,
                         const io::SpringModel& model, const io::ReducedExport* reduced) {
  const analysis::SpringNetwork& network = model.network;
  FileReport report("export", options.input, options.output);
  nlohmann::json& j = report.json;
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
    return any ? io::format_number(lo, 4) + " .. " + io::format_number(hi, 4) : std::string("-");
  };
  j["load_cases"] = model.load_cases.size();
  j["units"] = model.units;
  if (format == "mjcf" || format == "sofa") {
    const Eigen::Vector3d g = export_gravity(options.gravity, model);
    j["gravity"] = {g.x(), g.y(), g.z()};
    j["timestep"] = options.timestep;
  }
  if (reduced) {
    j["timestep"] = reduced->document.at("timestep");
    j["modes"] = options.modes;
    j["basis_size"] = reduced->basis_size;
    j["reduction_errors"] = reduced->document.at("errors");
  }
  io::MarkdownReport& md = report.markdown;
  md.heading(1, "isospring export: " + options.input + " -> " + options.output);
  md.table({"format", "particles", "fixed", "springs", "total mass [kg]", "stiffness [N/m]",
            "damping [N s/m]"},
           {{format, std::to_string(network.positions.size()), std::to_string(fixed),
             std::to_string(network.springs.size()), io::format_number(mass), range(k_min, k_max),
             range(c_min, c_max)}});
  if (reduced) {
    std::vector<std::vector<std::string>> rows;
    for (const io::ReducedLoadError& e : reduced->errors)
      rows.push_back({e.load, io::format_number(e.error.static_relative, 3),
                      io::format_number(e.error.projection_relative, 3),
                      e.error.exact_diverged ? "full network's run diverged"
                                             : io::format_number(e.error.dynamic_relative, 3),
                      e.error.exact_diverged ? "-" : io::format_number(e.error.dynamic_max, 3),
                      std::to_string(e.error.steps)});
    md.paragraph("Reduced model: " + std::to_string(reduced->basis_size) + " basis vectors (" +
                 std::to_string(options.modes) +
                 " modes + the load shapes); error against the full network from rest under "
                 "each load (docs/reduced_model.md):");
    md.table({"load", "static (relative)", "motion vs linearised network (rms relative)",
              "motion vs full network (rms relative)", "largest [m]", "steps"},
             rows);
  }
  report.write();
}

void run_export(const ExportOptions& options) {
  check_output_file(options.output, {options.input});
  const io::SpringModel model = io::read_model_json(options.input);
  const std::string format = format_of(options);
  const fs::path output = options.output;
  const std::string provenance =
      "source " + fs::path(options.input).filename().string() +
      (model.provenance.empty() ? std::string() : "; provenance " + model.provenance.dump());
  if (options.timestep < 0) throw nurbs::InputError("--timestep: must be >= 0 (0 = automatic)");
  std::optional<io::ReducedExport> reduced;
  if (format == "json") {
    io::write_spring_model_json(output, model);  // with its gravity and load cases
  } else if (format == "mjcf") {
    io::MjcfOptions o;
    o.model_name = fs::path(options.input).stem().string();
    o.gravity = export_gravity(options.gravity, model);
    o.timestep = options.timestep;
    o.comment = provenance;
    io::write_mjcf(output, model.network, o);
  } else if (format == "sofa") {
    io::SofaOptions o;
    o.gravity = export_gravity(options.gravity, model);
    o.timestep = options.timestep;
    o.comment = provenance;
    io::write_sofa_scene(output, model.network, o);
  } else if (format == "reduced") {
    io::ReducedExportOptions o;
    o.modes = options.modes;
    o.timestep = options.timestep > 0.0 ? options.timestep : 1e-3;
    reduced = io::export_reduced_model(model, o, {{"source", options.input}});
    io::write_file_atomically(output, reduced->document.dump() + "\n");
  } else if (output.extension() == ".vtm") {
    io::VtkScene scene;
    scene.network = model.network;
    io::write_vtk_scene(output, scene);
  } else {
    io::write_spring_network_vtp(output, model.network);
  }
  write_export_report(options, format, model, reduced ? &*reduced : nullptr);
  if (!options.quiet)
    std::cerr << "[export] wrote " << output.string() << " (" << format
              << "): " << model.network.positions.size() << " particles, "
              << model.network.springs.size() << " springs\n";
}

void setup_export(CLI::App& app) {
  auto options = std::make_shared<ExportOptions>();
  CLI::App* cmd = app.add_subcommand(
      "export", "Export a calibrated spring model (model.json) to MuJoCo, SOFA, VTK or JSON");
  cmd->add_option("MODEL", options->input, "Spring model written by `isospring calibrate`")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", options->output, "Output file")->required();
  cmd->add_option("--format", options->format,
                  "json | mjcf (MuJoCo 2.2 XML) | sofa (SOFA v22.12 .scn) | vtk (.vtp, or .vtm "
                  "multiblock) | reduced (modal model for haptic rates, JSON); default from the "
                  "output's extension (reduced: always give --format)")
      ->check(CLI::IsMember({"json", "mjcf", "sofa", "vtk", "reduced"}));
  cmd->add_option("--gravity", options->gravity,
                  "Gravity gx,gy,gz [m/s^2] for mjcf and sofa; default: the model's gravity, else "
                  "0,0,-9.81 (3D) or 0,-9.81,0 (a flat 2D model moves in x-y only)");
  cmd->add_option("--timestep", options->timestep,
                  "Time step [s]: mjcf and sofa, 0 = 0.2 x the explicit stability limit; reduced, "
                  "0 = 1e-3 (1 kHz)");
  cmd->add_option("--modes", options->modes,
                  "reduced: lowest natural modes in the basis (the model's load cases and gravity "
                  "join it as static shapes)")
      ->check(CLI::Range(1, 100000));
  cmd->add_flag("-q,--quiet", options->quiet, "No progress line on stderr");
  cmd->footer(
      "mjcf: free particles are bodies with slide joints, fixed ones sites in the world, springs\n"
      "spatial tendons (stiffness, damping, springlength = L0); contacts off.\n"
      "sofa: MechanicalObject + UniformMass/DiagonalMass + StiffSpringForceField + "
      "FixedConstraint.\n"
      "vtk: particles and springs with mass, fixed, stiffness, damping, rest_length, group.\n"
      "reduced: basis, eigenvalues, reduced damping and step matrix; the error against the full\n"
      "network per load goes into the report (docs/reduced_model.md).");
  cmd->callback([options] { run_export(*options); });
}

}  // namespace
ISOSPRING_REGISTER_COMMAND(80, setup_export);

}  // namespace isospring::apps
