#pragma once
// Patch files: NURBS patches as JSON.
//
//   {"patches": [{"degrees": [p, q(, r)],
//                 "knots": [[...], [...](, [...])],
//                 "control_points": [[x, y, z], ...],
//                 "weights": [...]}]}
//
// Full (open, clamped) knot vectors; control points ordered with the first parametric direction
// fastest; always 3 coordinates; `weights` optional (all 1 when absent). Every problem is an
// nurbs::InputError naming the file, the patch and the field.
#include <filesystem>
#include <nlohmann/json_fwd.hpp>
#include <vector>

#include "isospring/nurbs/patch.hpp"

namespace isospring::io {

/// Reads and validates a patch file.
std::vector<nurbs::Patch> read_patch_file(const std::filesystem::path& path);

/// Parses the JSON of a patch file; `source` names it in messages (a file name).
std::vector<nurbs::Patch> patches_from_json(const nlohmann::json& document,
                                            const std::string& source);

/// The JSON of a patch file (full double precision).
nlohmann::json patches_to_json(const std::vector<nurbs::Patch>& patches);

/// Writes a patch file atomically.
void write_patch_file(const std::filesystem::path& path, const std::vector<nurbs::Patch>& patches);

}  // namespace isospring::io
