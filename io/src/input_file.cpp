// Input kinds and the files an input reads (see input_file.hpp).
#include "isospring/io/input_file.hpp"

#include <algorithm>
#include <nlohmann/json.hpp>

#include "isospring/geometry/cad.hpp"
#include "isospring/io/atomic_file.hpp"
#include "isospring/io/json_text.hpp"
#include "isospring/io/patch_file.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::io {

InputKind input_kind(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension == ".step" || extension == ".stp" || extension == ".iges" || extension == ".igs")
    return InputKind::kCad;
  // JSON: a patch file has "patches" at the top level, a case file has "geometry".
  const nlohmann::json document = parse_json_text(read_text_file(path, "input file"), path.string(),
                                                  "patch file, a case file or a STEP/IGES part");
  if (document.is_object() && document.contains("patches")) return InputKind::kPatchFile;
  if (document.is_object() && document.contains("geometry")) return InputKind::kCaseFile;
  throw nurbs::InputError(path.string() +
                          ": neither a patch file (no \"patches\") nor a case file (no "
                          "\"geometry\"); see docs/case-files.md for both formats");
}

std::vector<nurbs::Patch> read_patches_any(const std::filesystem::path& path) {
  switch (input_kind(path)) {
    case InputKind::kCad:
      return geometry::cad_patches(geometry::read_cad(path));
    case InputKind::kCaseFile:
      return read_case_file(path).problem.patches;
    case InputKind::kPatchFile:
      break;
  }
  return read_patch_file(path);
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

std::vector<std::filesystem::path> case_inputs(const Case& c) {
  return referenced_files(c.file, c.raw);
}

std::vector<std::filesystem::path> input_files(const std::filesystem::path& path) {
  if (input_kind(path) != InputKind::kCaseFile) return {path};
  return referenced_files(
      path, parse_json_text(read_text_file(path, "case file"), path.string(), "case file"));
}

}  // namespace isospring::io
