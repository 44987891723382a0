#pragma once
// A CAD part's display triangulation (geometry/cad_triangulation.hpp) as VTK poly data (.vtp):
// triangles with cell data `face` (the face index that `isospring info` lists).
#include <filesystem>

#include "isospring/geometry/cad_triangulation.hpp"

namespace isospring::io {

/// Writes atomically; throws nurbs::InputError naming the path when it cannot be written.
void write_triangulation_vtp(const std::filesystem::path& path,
                             const geometry::CadTriangulation& mesh);

}  // namespace isospring::io
