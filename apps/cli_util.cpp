#include "cli_util.hpp"

#include <cmath>
#include <sstream>

#include <algorithm>
#include <nlohmann/json.hpp>

#include "isospring/geometry/cad.hpp"
#include "isospring/io/atomic_file.hpp"
#include "isospring/io/case_file.hpp"
#include "isospring/io/patch_file.hpp"
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
  nlohmann::json document;
  try {
    document = nlohmann::json::parse(io::read_text_file(path, "input file"));
  } catch (const nlohmann::json::exception& e) {
    throw nurbs::InputError(path.string() + ": not valid JSON (" + e.what() +
                            "); give a patch file, a case file or a STEP/IGES part");
  }
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

std::filesystem::path output_folder(const std::string& option_value) {
  const std::filesystem::path folder(option_value);
  if (std::filesystem::exists(folder) && !std::filesystem::is_directory(folder))
    throw nurbs::InputError("-o " + option_value +
                            ": exists and is not a folder; give a folder for the outputs");
  return folder;
}

}  // namespace isospring::apps
