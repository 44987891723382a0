#pragma once
// Refinement of a display triangulation for fields: OpenCascade meshes a planar face with a few
// long triangles (its deflection is zero anyway), and a field evaluated only at their corners is
// interpolated linearly over the whole face, which shows as stripes of false stress in ParaView.
// Each triangle whose longest edge exceeds `max_edge` is split uniformly into k^2 triangles,
// k = ceil(longest edge / max_edge), its new points on the flat triangle (within the mesh's
// deflection of the face). Points on an edge are shared with the neighbour when it splits that
// edge alike; otherwise the neighbour's coarser edge has hanging points on it, which lie on its
// straight edge, so the surface has no gaps.
#include <filesystem>

#include "isospring/geometry/cad_triangulation.hpp"
#include "isospring/geometry/immersed_domain.hpp"

namespace isospring::workflows::detail {

/// The display triangulation of an immersed part (the faces of `part` that the domain's boundary
/// points lie on; a file may hold several solids), within 1e-3 of the part's diagonal, its
/// triangles split to at most a background cell's edge: the fields vary on that scale, and
/// ParaView interpolates them linearly.
geometry::CadTriangulation immersed_part_surface(const std::filesystem::path& part,
                                                 const geometry::ImmersedDomain& domain);

geometry::CadTriangulation refine_triangulation(const geometry::CadTriangulation& mesh,
                                                double max_edge);

}  // namespace isospring::workflows::detail
