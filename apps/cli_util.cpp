#include "cli_util.hpp"

#include <cmath>
#include <sstream>

#include <algorithm>
#include <nlohmann/json.hpp>

#include "file_report.hpp"
#include "isospring/analysis/resource_estimate.hpp"
#include "isospring/geometry/cad.hpp"
#include "isospring/io/atomic_file.hpp"
#include "isospring/io/case_file.hpp"
#include "isospring/io/json_text.hpp"
#include "isospring/io/output_guard.hpp"
#include "isospring/io/patch_file.hpp"
#include "isospring/io/report.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::apps {

std::vector<double> parse_number_list(const std::string& text, const std::string& option) {
  std::vector<double> values;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    size_t used = 0;
    double value = 0.0;
    try {
      value = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size() || !std::isfinite(value))
      throw nurbs::InputError(option + ": '" + item + "' in '" + text +
                              "' is not a number; give comma-separated numbers like 0.25,0.5");
    values.push_back(value);
  }
  if (values.empty()) throw nurbs::InputError(option + ": no numbers given");
  return values;
}

InputKind input_kind(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension == ".step" || extension == ".stp" || extension == ".iges" || extension == ".igs")
    return InputKind::kCad;
  // JSON: a patch file has "patches" at the top level, a case file has "geometry".
  const nlohmann::json document =
      io::parse_json_text(io::read_text_file(path, "input file"), path.string(),
                          "patch file, a case file or a STEP/IGES part");
  if (document.is_object() && document.contains("patches")) return InputKind::kPatchFile;
  if (document.is_object() && document.contains("geometry")) return InputKind::kCaseFile;
  throw nurbs::InputError(path.string() +
                          ": neither a patch file (no \"patches\") nor a case file (no "
                          "\"geometry\"); see the README for both formats");
}

std::vector<nurbs::Patch> read_patches_any(const std::filesystem::path& path) {
  switch (input_kind(path)) {
    case InputKind::kCad:
      return geometry::cad_patches(geometry::read_cad(path));
    case InputKind::kCaseFile:
      return io::read_case_file(path).problem.patches;
    case InputKind::kPatchFile:
      break;
  }
  return io::read_patch_file(path);
}

std::vector<std::filesystem::path> in_folder(const std::filesystem::path& folder,
                                             const std::vector<std::string>& names) {
  std::vector<std::filesystem::path> paths;
  for (const std::string& name : names) paths.push_back(folder / name);
  return paths;
}

std::filesystem::path output_folder(const std::string& option_value,
                                    const std::vector<std::filesystem::path>& inputs,
                                    const std::vector<std::string>& names) {
  const std::filesystem::path folder(option_value);
  if (std::filesystem::exists(folder) && !std::filesystem::is_directory(folder))
    throw nurbs::InputError("-o " + option_value +
                            ": exists and is not a folder; give a folder for the outputs");
  io::check_outputs_spare_inputs(inputs, in_folder(folder, names));
  io::check_writable_folder(folder);
  return folder;
}

void check_output_file(const std::filesystem::path& output,
                       const std::vector<std::filesystem::path>& inputs,
                       const std::vector<std::filesystem::path>& extra) {
  if (std::filesystem::is_directory(output))
    throw nurbs::InputError("-o " + output.string() +
                            ": is a folder; give the name of the file to write");
  std::vector<std::filesystem::path> outputs = extra;
  outputs.push_back(output);
  outputs.push_back(file_report_path(output, ".json"));
  outputs.push_back(file_report_path(output, ".md"));
  io::check_outputs_spare_inputs(inputs, outputs);
  io::check_writable_folder(output.parent_path());
  for (const std::filesystem::path& other : extra) io::check_writable_folder(other.parent_path());
}

MemoryLimit memory_limit(double max_memory_gb) {
  MemoryLimit limit{analysis::available_memory_bytes(),
                    "available memory, MemAvailable in /proc/meminfo"};
  if (max_memory_gb > 0 && (limit.bytes <= 0 || max_memory_gb * 1e9 < limit.bytes))
    limit = {max_memory_gb * 1e9, "--max-memory " + io::format_number(max_memory_gb) + " GB"};
  return limit;
}

io::CaseLimits solve_limits(double max_memory_gb) {
  const MemoryLimit limit = memory_limit(max_memory_gb);
  io::CaseLimits limits;
  limits.solve_memory_bytes = limit.bytes;
  limits.solve_memory_source = limit.source;
  return limits;
}

namespace {
// The case file and the files its document names: geometry.file and measurements.file.
std::vector<std::filesystem::path> referenced_files(const std::filesystem::path& case_file,
                                                    const nlohmann::json& document) {
  std::vector<std::filesystem::path> inputs{case_file};
  for (const char* section : {"geometry", "measurements"}) {
    if (!document.is_object() || !document.contains(section)) continue;
    const nlohmann::json& object = document[section];
    if (object.is_object() && object.contains("file") && object["file"].is_string())
      inputs.push_back(case_file.parent_path() / object["file"].get<std::string>());
  }
  return inputs;
}
}  // namespace

std::vector<std::filesystem::path> case_inputs(const io::Case& c) {
  return referenced_files(c.file, c.raw);
}

std::vector<std::filesystem::path> input_files(const std::filesystem::path& path) {
  if (input_kind(path) != InputKind::kCaseFile) return {path};
  return referenced_files(
      path, io::parse_json_text(io::read_text_file(path, "case file"), path.string(), "case file"));
}

}  // namespace isospring::apps
