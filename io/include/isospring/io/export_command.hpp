#pragma once
// The use case behind `isospring export MODEL.json -o OUT [--format json|mjcf|sofa|vtk]`: a
// calibrated spring model (model.json) for real-time engines and viewers: MuJoCo MJCF, a SOFA
// scene, VTK poly data, or a validated, normalised model.json; and the report of what the engine
// receives (counts, mass, stiffness and damping ranges, loads).
#include <nlohmann/json.hpp>
#include <string>

#include "isospring/io/model_file.hpp"
#include "isospring/io/report.hpp"

namespace isospring::io {

struct ExportCommandOptions {
  std::string input, output;
  std::string format;     // json | mjcf | sofa | vtk; empty: from the output's extension
  std::string gravity;    // "gx,gy,gz" for mjcf and sofa; empty: io::engine_gravity's default
  double timestep = 0.0;  // for mjcf and sofa; 0: automatic
};

struct ExportCommandResult {
  std::string format;
  SpringModel model;
};

/// Reads options.input and writes options.output. Throws nurbs::InputError for bad options and
/// models.
ExportCommandResult run_export(const ExportCommandOptions& options);

/// The report's content beside the output (FileReport's json and markdown).
void export_report(const ExportCommandResult& r, const ExportCommandOptions& options,
                   nlohmann::json& json, MarkdownReport& md);

}  // namespace isospring::io
