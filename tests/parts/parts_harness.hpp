// The parts harness: a part of tests/data/parts/parts.json as the CalculiX script sets it up
// (its file placed, its background grid, its clamp, gravity and material), shared by the tests
// against CalculiX and the stabilisation tests that reuse their parts.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "isospring/analysis/immersed.hpp"
#include "isospring/geometry/immersed_cad.hpp"

namespace isospring::parts_harness {

/// tests/data/parts: the third-party parts, parts.json and calculix_reference.json.
extern const std::filesystem::path kParts;

nlohmann::json read_json(const std::filesystem::path& path);

/// parts.json's entry `name` (null when there is none).
nlohmann::json find_part(const std::string& name);

/// parts.json's "placement": {"axis": [x, y, z], "angle_deg": a}, the rotation by a degrees
/// about the axis through the origin that the CalculiX script applies with gmsh's occ.rotate
/// (identity without it).
Eigen::Matrix3d placement(const nlohmann::json& part);

/// The part as the CalculiX script meshes it: read from its file and placed by "placement".
geometry::CadSolid read_placed_solid(const nlohmann::json& part);

/// The background grid of parts.json's "immersed" options `grid` at `degree`: "frame":
/// "placement" puts it in the placement's frame, "principal" in the part's principal axes, else
/// it follows the world's axes; "grading" and "grading_planes" grade the cells.
geometry::ImmersionOptions immersion_options(const nlohmann::json& part, const nlohmann::json& grid,
                                             int degree, const geometry::CadSolid& solid);

/// The problem of `part`: its material, the clamp on its face, its gravity, and the grid options'
/// formulation and ghost penalty.
analysis::ImmersedOptions analysis_options(const nlohmann::json& part, const nlohmann::json& grid);

}  // namespace isospring::parts_harness
