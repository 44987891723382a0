#pragma once
// The spring network as VTK poly data (.vtp): particles are the points, springs the lines.
// Cell data: stiffness, damping, rest_length, group. Point data: mass, fixed (0/1) and one
// displacement vector array per load case (or per frame quantity) when given.
#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "isospring/analysis/spring_network.hpp"

namespace isospring::io {

/// A named vector per point (displacements of one load case, velocities of a frame...).
struct PointVectors {
  std::string name;
  std::vector<Eigen::Vector3d> values;
};

/// Points at the rest positions plus `deformation` (empty: at rest); `vectors` must have one
/// value per particle (std::invalid_argument otherwise, a caller bug).
void write_spring_network_vtp(const std::filesystem::path& path,
                              const analysis::SpringNetwork& network,
                              const std::vector<PointVectors>& vectors = {},
                              const std::vector<Eigen::Vector3d>& deformation = {});

}  // namespace isospring::io
