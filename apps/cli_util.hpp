#pragma once
// Small helpers shared by the subcommands: parsing parameter lists and reading patch inputs.
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

/// Patches of a patch file, a case file (its discretised geometry) or a CAD file, by content.
std::vector<nurbs::Patch> read_patches_any(const std::filesystem::path& path);

}  // namespace isospring::apps
