#include "isospring/io/vtk_triangulation.hpp"

#include "isospring/io/vtk_surface_fields.hpp"

namespace isospring::io {

// The triangulation alone is the surface-field file without point fields (the face index per
// triangle as cell data), written by the one writer of such files.
void write_triangulation_vtp(const std::filesystem::path& path,
                             const geometry::CadTriangulation& mesh) {
  write_surface_fields_vtp(path, mesh, {});
}

}  // namespace isospring::io
