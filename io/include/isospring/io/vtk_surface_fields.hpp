#pragma once
// Fields on a CAD part's display triangulation as VTK poly data (.vtp): the results of an
// immersed analysis shown on the part itself, not on its background grid.
#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "isospring/geometry/cad_triangulation.hpp"

namespace isospring::io {

/// One value per triangulation point: 3-component vectors or scalars.
struct SurfacePointField {
  std::string name;
  std::vector<Eigen::Vector3d> vectors;  // used when not empty
  std::vector<double> scalars;
};

/// Triangles with cell data `face` and the given point data. Every field must have one value per
/// point (std::invalid_argument otherwise: a caller bug). Writes atomically; throws
/// nurbs::InputError naming the path when it cannot be written.
void write_surface_fields_vtp(const std::filesystem::path& path,
                              const geometry::CadTriangulation& mesh,
                              const std::vector<SurfacePointField>& fields);

}  // namespace isospring::io
