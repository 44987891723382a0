#pragma once
// The use case behind `isospring info FILE`: what a patch file, a case file or a CAD part holds:
// per patch its dimensions, degrees, knot vectors (unique knots with multiplicities), control
// points, elements, bounding box and length/area/volume; for a case file also its material,
// supports and loads; for a CAD part OpenCascade's own report (units, faces, volume and area).
#include <nlohmann/json.hpp>
#include <string>

namespace isospring::workflows {

/// For people: the text `isospring info` prints (10 significant digits).
std::string file_info_text(const std::string& file);

/// For scripts (`--json`): {"file", "kind", "patches": [patch_json], "total_measure"} plus "case"
/// (name, formulation, material, supports, load_cases) or "cad" (unit, counts, volume, area,
/// faces usable).
nlohmann::json file_info_json(const std::string& file);

}  // namespace isospring::workflows
