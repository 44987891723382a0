// export-step as a use case (export_step_command.hpp); the program only parses flags, checks the
// output path against the input and prints.
#include "isospring/workflows/export_step_command.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "isospring/io/input_file.hpp"
#include "isospring/io/report_patch.hpp"

namespace isospring::workflows {
// The use cases read and write io's formats; io's names are used unqualified here.
using namespace isospring::io;

ExportStepCommandResult run_export_step(const ExportStepCommandOptions& options) {
  ExportStepCommandResult r;
  r.patches = read_patches_any(options.input);
  r.written = geometry::write_cad(options.output, r.patches);
  const std::filesystem::path output(options.output);
  // write_cad chooses the format by the lower-cased extension; so does the report (the program
  // used to report .Igs, which write_cad writes as IGES, as STEP).
  std::string ext = output.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  r.format = ext == ".iges" || ext == ".igs" ? "iges" : "step";
  r.file_bytes = std::filesystem::file_size(output);
  return r;
}

void export_step_report(const ExportStepCommandResult& r, const ExportStepCommandOptions& options,
                        nlohmann::json& json, MarkdownReport& md) {
  json["format"] = r.format;
  json["patches"] = r.patches.size();
  json["faces"] = r.written.faces;
  json["solids"] = r.written.solids;
  json["warnings"] = r.written.notes;
  json["file_bytes"] = r.file_bytes;
  json["units"] = "m";
  md.heading(1, "isospring export-step: " + options.input);
  md.paragraph(std::to_string(r.patches.size()) + " patches written to " + options.output + " as " +
               std::to_string(r.written.faces) + " B-spline faces, " +
               std::to_string(r.written.solids) +
               " closed solid(s) (every volume patch as its six sides sewn), in m; " +
               std::to_string(r.file_bytes) + " bytes.");
  if (!r.written.notes.empty()) {
    std::vector<std::string> items;
    for (const auto& note : r.written.notes) items.push_back("Warning: " + note);
    md.bullets(items);
  }
  md.table(patch_table_header(), patch_table_rows(r.patches));
}

std::string export_step_summary(const ExportStepCommandResult& r,
                                const ExportStepCommandOptions& options) {
  return "wrote " + options.output + ": " + std::to_string(r.patches.size()) + " patches (" +
         std::to_string(r.written.solids) + " solid(s))";
}

}  // namespace isospring::workflows
