#pragma once
// The use case behind `isospring export-step IN -o OUT.step|.igs`: the patches of a patch, case
// or CAD file written as B-spline faces to STEP or IGES (geometry::write_cad: volumes as closed
// solids, in metres), and the report of what was written.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "isospring/geometry/cad.hpp"
#include "isospring/io/report.hpp"
#include "isospring/nurbs/patch.hpp"

namespace isospring::workflows {

struct ExportStepCommandOptions {
  std::string input;   // patch file, case file or CAD file (read_patches_any)
  std::string output;  // .step/.stp or .iges/.igs: write_cad chooses by extension
};

struct ExportStepCommandResult {
  std::vector<nurbs::Patch> patches;  // as read from the input, in order
  geometry::CadWriteSummary written;
  std::string format;             // "iges" or "step", the format the output's extension selected
  std::uintmax_t file_bytes = 0;  // of the file written
};

/// Reads options.input and writes options.output. Throws nurbs::InputError for unreadable
/// inputs and output names write_cad refuses.
ExportStepCommandResult run_export_step(const ExportStepCommandOptions& options);

/// The report's content beside the output (FileReport's json and markdown).
void export_step_report(const ExportStepCommandResult& r, const ExportStepCommandOptions& options,
                        nlohmann::json& json, io::MarkdownReport& md);

/// The line the program prints unless quiet: what was written.
std::string export_step_summary(const ExportStepCommandResult& r,
                                const ExportStepCommandOptions& options);

}  // namespace isospring::workflows
