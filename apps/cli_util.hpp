#pragma once
// Small helpers shared by the subcommands: parsing parameter lists, reading patch inputs and
// checking the output folder.
#include <filesystem>
#include <string>
#include <vector>

#include "isospring/nurbs/patch.hpp"

namespace isospring::apps {

/// "0.3,0.5" -> {0.3, 0.5}; throws nurbs::InputError naming `option` on anything else.
std::vector<double> parse_number_list(const std::string& text, const std::string& option);

enum class InputKind { kPatchFile, kCaseFile, kCad };

/// STEP/IGES by extension; JSON by content ("patches" -> patch file, "geometry" -> case file).
InputKind input_kind(const std::filesystem::path& path);

/// The output folder given with -o, checked before any work: throws nurbs::InputError when the
/// path exists and is not a folder. The folder itself is created when the outputs are written.
std::filesystem::path output_folder(const std::string& option_value);

/// Patches of a patch file, a case file (its discretised geometry) or a CAD file, by content.
std::vector<nurbs::Patch> read_patches_any(const std::filesystem::path& path);

}  // namespace isospring::apps
