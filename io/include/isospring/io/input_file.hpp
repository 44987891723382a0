#pragma once
// What an input file is and which files reading it reads: the three kinds every command that
// takes "a geometry" accepts (a patch file, a case file, a STEP/IGES part), told apart by
// extension and content, so a library user and the program decide alike.
#include <filesystem>
#include <vector>

#include "isospring/io/case_file.hpp"
#include "isospring/nurbs/patch.hpp"

namespace isospring::io {

enum class InputKind { kPatchFile, kCaseFile, kCad };

/// STEP/IGES by extension; JSON by content ("patches" -> patch file, "geometry" -> case file);
/// anything else is a nurbs::InputError.
InputKind input_kind(const std::filesystem::path& path);

/// Patches of a patch file, a case file (its discretised geometry) or a CAD file, by content.
std::vector<nurbs::Patch> read_patches_any(const std::filesystem::path& path);

/// Every file a case reads: the case file, its geometry file (CAD or patch file) and its
/// measurements file.
std::vector<std::filesystem::path> case_inputs(const Case& c);

/// Every file reading `path` reads: the file itself and, for a case file, its geometry and
/// measurements files (from the document, before the case is built).
std::vector<std::filesystem::path> input_files(const std::filesystem::path& path);

}  // namespace isospring::io
