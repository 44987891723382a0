// The export format table (export_formats.hpp) and the formats' adapters from the command's
// options to their writers.
#include "isospring/workflows/export_formats.hpp"

#include <filesystem>
#include <optional>

#include "isospring/io/atomic_file.hpp"
#include "isospring/io/export_mjcf.hpp"
#include "isospring/io/export_reduced.hpp"
#include "isospring/io/export_sofa.hpp"
#include "isospring/io/number_list.hpp"
#include "isospring/io/vtk_multiblock.hpp"
#include "isospring/io/vtk_spring_network.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::workflows {
// The use cases read and write io's formats; io's names are used unqualified here.
using namespace isospring::io;
namespace {
namespace fs = std::filesystem;

// The comment the engine scenes carry: where the model came from.
std::string provenance(const ExportCommandOptions& options, const SpringModel& model) {
  return "source " + fs::path(options.input).filename().string() +
         (model.provenance.empty() ? std::string() : "; provenance " + model.provenance.dump());
}

void write_json(const ExportCommandOptions& options, ExportCommandResult& r) {
  write_spring_model_json(options.output, r.model);  // with its gravity and load cases
}

void write_mjcf_scene(const ExportCommandOptions& options, ExportCommandResult& r) {
  MjcfOptions o;
  o.model_name = fs::path(options.input).stem().string();
  o.gravity = export_gravity(options.gravity, r.model);
  o.timestep = options.timestep;
  o.comment = provenance(options, r.model);
  write_mjcf(options.output, r.model.network, o);
}

void write_sofa(const ExportCommandOptions& options, ExportCommandResult& r) {
  SofaOptions o;
  o.gravity = export_gravity(options.gravity, r.model);
  o.timestep = options.timestep;
  o.comment = provenance(options, r.model);
  write_sofa_scene(options.output, r.model.network, o);
}

// .vtm: a multiblock scene (the network as one block); otherwise the network as .vtp.
void write_vtk(const ExportCommandOptions& options, ExportCommandResult& r) {
  if (fs::path(options.output).extension() == ".vtm") {
    VtkScene scene;
    scene.network = r.model.network;
    write_vtk_scene(options.output, scene);
  } else {
    write_spring_network_vtp(options.output, r.model.network);
  }
}

void write_reduced(const ExportCommandOptions& options, ExportCommandResult& r) {
  ReducedExportOptions o;
  o.modes = options.modes;
  o.timestep = options.timestep > 0.0 ? options.timestep : 1e-3;
  o.corotated = options.corotated;
  r.reduced = export_reduced_model(r.model, o, {{"source", options.input}});
  write_file_atomically(options.output, r.reduced->document.dump() + "\n");
}

}  // namespace

const std::vector<ExportFormat>& export_formats() {
  static const std::vector<ExportFormat> formats{
      {"json", {".json"}, "the validated, normalised model.json", false, write_json},
      {"mjcf", {".xml", ".mjcf"}, "MuJoCo 2.2 XML", true, write_mjcf_scene},
      {"sofa", {".scn"}, "SOFA v22.12 .scn", true, write_sofa},
      {"vtk", {".vtp", ".vtm"}, ".vtp, or .vtm multiblock", false, write_vtk},
      {"reduced", {}, "modal model for haptic rates, JSON", false, write_reduced},
  };
  return formats;
}

const ExportFormat& export_format(const std::string& name) {
  for (const ExportFormat& format : export_formats())
    if (format.name == name) return format;
  std::string names;
  for (const ExportFormat& format : export_formats())
    names += (names.empty() ? "" : "|") + format.name;
  throw nurbs::InputError("--format " + name + ": not a format; use " + names);
}

const ExportFormat& export_format_of(const ExportCommandOptions& options) {
  if (!options.format.empty()) return export_format(options.format);
  const std::string ext = fs::path(options.output).extension().string();
  std::string names, extensions;
  for (const ExportFormat& format : export_formats()) {
    for (const std::string& e : format.extensions)
      if (e == ext) return format;
    if (format.extensions.empty()) continue;
    names += (names.empty() ? "" : "|") + format.name;
    for (const std::string& e : format.extensions)
      extensions += (extensions.empty() ? "" : ", ") + e;
  }
  throw nurbs::InputError("-o " + options.output +
                          ": cannot tell the format from the extension; add --format " + names +
                          " (or use " + extensions + ")");
}

std::string export_formats_help() {
  std::string help;
  for (const ExportFormat& format : export_formats())
    help += (help.empty() ? "" : " | ") + format.name + " (" + format.description + ")";
  std::string by_extension;
  for (const ExportFormat& format : export_formats())
    for (const std::string& e : format.extensions)
      by_extension += (by_extension.empty() ? "" : ", ") + e + " " + format.name;
  return help + "; default from the output's extension (" + by_extension +
         "; the others: always give --format)";
}

Eigen::Vector3d export_gravity(const std::string& text, const SpringModel& model) {
  std::optional<Eigen::Vector3d> given;
  if (!text.empty()) {
    const std::vector<double> g = parse_number_list(text, "--gravity");
    if (g.size() != 3) throw nurbs::InputError("--gravity: give three numbers gx,gy,gz in m/s^2");
    given = Eigen::Vector3d(g[0], g[1], g[2]);
  }
  return engine_gravity(model.network, model.gravity, given);
}

}  // namespace isospring::workflows
