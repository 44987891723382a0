#pragma once
// The use case behind `isospring export MODEL.json -o OUT [--format json|mjcf|sofa|vtk|reduced]`:
// a calibrated spring model (model.json) for real-time engines and viewers: MuJoCo MJCF, a SOFA
// scene, VTK poly data, a validated, normalised model.json, or its reduced (modal + load shapes)
// model for haptic rates (docs/reduced_model.md); and the report of what the engine receives
// (counts, mass, stiffness and damping ranges, loads; the reduced model's errors). The formats
// are one table, export_formats.hpp.
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "isospring/io/export_reduced.hpp"
#include "isospring/io/model_file.hpp"
#include "isospring/io/report.hpp"

namespace isospring::workflows {

struct ExportCommandOptions {
  std::string input, output;
  std::string format;      // an export_formats() name; empty: from the output's extension
  std::string gravity;     // "gx,gy,gz" for mjcf and sofa; empty: io::engine_gravity's default
  double timestep = 0.0;   // mjcf and sofa: 0 = automatic; reduced: 0 = 1e-3 s
  int modes = 32;          // reduced: lowest natural modes in the basis
  bool corotated = false;  // reduced: the corotated model (docs/reduced_model.md, large rotation)
};

struct ExportCommandResult {
  std::string format;  // the export_formats() name written
  io::SpringModel model;
  std::optional<io::ReducedExport> reduced;  // format reduced: the document and its errors
};

/// Reads options.input and writes options.output. Throws nurbs::InputError for bad options and
/// models.
ExportCommandResult run_export(const ExportCommandOptions& options);

/// The report's content beside the output (FileReport's json and markdown).
void export_report(const ExportCommandResult& r, const ExportCommandOptions& options,
                   nlohmann::json& json, io::MarkdownReport& md);

}  // namespace isospring::workflows
