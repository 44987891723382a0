#pragma once
// Measured markers as VTK poly data (.vtp): one vertex per marker with, per load case,
// "measured_<case>", "model_<case>", "residual_<case>" (measured - model) and
// "residual_magnitude_<case>".
#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

namespace isospring::io {

struct MarkerCase {
  std::string load_case;
  std::vector<Eigen::Vector3d> measured;  // one per marker
  std::vector<Eigen::Vector3d> model;     // model displacement at the marker
};

struct MarkerData {
  std::vector<Eigen::Vector3d> positions;
  std::vector<MarkerCase> cases;
};

void write_markers_vtp(const std::filesystem::path& path, const MarkerData& markers);

}  // namespace isospring::io
