#pragma once
// Reports of the commands that write ONE file (import, refine, export, export-calculix,
// export-step): beside the output, <dir>/<file name>.report.json and .report.md, the output's
// whole name with its extension, e.g. `-o out/part.json` -> out/part.json.report.json and
// out/part.json.report.md, so `part.step` and `part.igs` beside `part.json` each keep their own
// report. The commands that write a folder put report.json / report.md into it instead
// (docs/outputs.md).
#include <chrono>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "isospring/io/report.hpp"
#include "isospring/io/report_patch.hpp"
#include "isospring/nurbs/patch.hpp"

namespace isospring::apps {

/// out/part.json -> out/part.json.report.json (extension ".json") or out/part.json.report.md.
std::filesystem::path file_report_path(const std::filesystem::path& output,
                                       const std::string& extension);

/// One command's report: the header every report.json has (io::report_header), "output", and
/// "seconds" since construction, filled by the command; written beside the output.
class FileReport {
 public:
  FileReport(const std::string& command, const std::filesystem::path& input,
             const std::filesystem::path& output);
  nlohmann::json json;
  io::MarkdownReport markdown;
  /// Writes both files atomically; returns the JSON's path.
  std::filesystem::path write();

 private:
  std::filesystem::path output_;
  std::chrono::steady_clock::time_point start_;
};

// A patch in reports is the library's (io/report_patch.hpp).
using io::patch_json;
using io::patch_table_header;
using io::patch_table_rows;

}  // namespace isospring::apps
