#pragma once
// The background cells of an immersed domain as VTK hexahedra (.vtu), for those who want to see
// the grid the part is embedded in: every active cell (inside or cut) with cell data `kind`
// (0 inside, 1 cut) and `fraction`, the part's share of the cell's volume (the sum of the cell's
// quadrature weights over the cell's volume; 1 inside, between 0 and 1 when cut).
#include <filesystem>

#include "isospring/geometry/immersed_domain.hpp"

namespace isospring::io {

/// Writes atomically; throws nurbs::InputError naming the path when it cannot be written. 3D
/// domains only (std::invalid_argument otherwise: a caller bug).
void write_immersed_cells_vtu(const std::filesystem::path& path,
                              const geometry::ImmersedDomain& domain);

}  // namespace isospring::io
