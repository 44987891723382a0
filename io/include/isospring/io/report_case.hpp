#pragma once
// Report pieces every command that reads a case file shares: the inputs summary and the
// control-point displacement table.
#include <Eigen/Core>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "isospring/io/case_file.hpp"
#include "isospring/io/report.hpp"

namespace isospring::io {

/// "plane_stress", "plane_strain" or "solid".
std::string formulation_name(analysis::Formulation formulation);

/// The inputs of a case as reports show them: name, file, dimension, formulation, material,
/// discretisation, patches, control points, elements, load-case ids (for `problem`, which may be
/// the case's own problem or one at another discretisation).
nlohmann::json case_summary(const Case& c, const analysis::Problem& problem);

/// The same as Markdown bullets.
void add_case_summary(MarkdownReport& report, const nlohmann::json& summary);

/// CSV `i,x,y,z,ux,uy,uz`, one row per control point of every patch in order (i counts over the
/// patches, so a point shared by two patches appears once per patch), full double precision.
void write_control_displacements_csv(
    const std::filesystem::path& path, const std::vector<nurbs::Patch>& patches,
    const std::vector<std::vector<Eigen::Vector3d>>& control_displacements);

}  // namespace isospring::io
