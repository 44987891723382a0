#pragma once
// Refinement of a display triangulation for fields: OpenCascade meshes a planar face with a few
// long triangles (its deflection is zero anyway), and a field evaluated only at their corners is
// interpolated linearly over the whole face, which shows as stripes of false stress in ParaView.
// Each triangle whose longest edge exceeds `max_edge` is split uniformly into k^2 triangles,
// k = ceil(longest edge / max_edge), its new points on the flat triangle (within the mesh's
// deflection of the face). Points on an edge are shared with the neighbour when it splits that
// edge alike; otherwise the neighbour's coarser edge has hanging points on it, which lie on its
// straight edge, so the surface has no gaps.
#include "isospring/geometry/cad_triangulation.hpp"

namespace isospring::workflows::detail {

geometry::CadTriangulation refine_triangulation(const geometry::CadTriangulation& mesh,
                                                double max_edge);

}  // namespace isospring::workflows::detail
