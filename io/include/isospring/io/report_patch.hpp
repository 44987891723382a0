#pragma once
// A patch in reports (report.json and report.md of import, refine, export and info).
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "isospring/nurbs/patch.hpp"

namespace isospring::io {

/// Parametric and physical dimension, rational, degrees, control points per direction, elements
/// per direction, control-net bounding box, and its length / area / volume ("measure",
/// geometry::measure).
nlohmann::json patch_json(const nurbs::Patch& patch);

/// One Markdown table row per patch: index, dimension, degrees, control points, elements, measure.
std::vector<std::string> patch_table_header();
std::vector<std::vector<std::string>> patch_table_rows(const std::vector<nurbs::Patch>& patches);

}  // namespace isospring::io
