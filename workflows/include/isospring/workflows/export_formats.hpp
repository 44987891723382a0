#pragma once
// The formats of `isospring export` (export_command.hpp) as one table: run_export dispatches on
// it, the output's extension selects from it, and the program's --format check and help are
// built from it. A new format is a writer (its own file, like export_mjcf.cpp) and one entry of
// export_formats() (workflows/src/export_formats.cpp); nothing else names the formats.
//
// An explicit table rather than self-registering writers: the io library is static, and a
// linker leaves out an object file that nothing refers to, so a self-registering format would
// silently be missing from the program.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "isospring/workflows/export_command.hpp"

namespace isospring::workflows {

struct ExportFormat {
  std::string name;  // the --format value, and ExportCommandResult::format
  /// Output extensions that select the format when --format is not given (".xml"); empty: only
  /// by --format (reduced writes .json, which means the model itself).
  std::vector<std::string> extensions;
  std::string description;  // for --format's help
  /// A scene for a physics engine: it takes --gravity and --timestep, and the report shows them.
  bool engine_scene = false;
  /// Writes result.model to options.output (and may fill the result's format-specific parts,
  /// e.g. result.reduced). Throws nurbs::InputError for options the format cannot take.
  void (*write)(const ExportCommandOptions& options, ExportCommandResult& result) = nullptr;
};

/// Every export format, in the order --format's help lists them.
const std::vector<ExportFormat>& export_formats();

/// The format named `name`; throws nurbs::InputError naming the formats when there is none.
const ExportFormat& export_format(const std::string& name);

/// options.format when given, else the format whose extensions hold the output's extension;
/// throws nurbs::InputError when neither tells.
const ExportFormat& export_format_of(const ExportCommandOptions& options);

/// "name (description) | ..." for the program's --format help.
std::string export_formats_help();

/// --gravity ("gx,gy,gz"), or engine_gravity's default for the model (the model's own, else -z in
/// 3D and -y for a flat model); a z gravity for a flat model is refused.
Eigen::Vector3d export_gravity(const std::string& text, const io::SpringModel& model);

}  // namespace isospring::workflows
