// The display triangulation of an immersed part (see surface_refinement.hpp).
#include <algorithm>
#include <array>
#include <limits>
#include <map>
#include <set>

#include "surface_refinement.hpp"

namespace isospring::workflows::detail {
namespace {

/// The triangles of the solid's own faces (a file may hold several solids), points renumbered.
geometry::CadTriangulation solid_surface(const geometry::CadTriangulation& all,
                                         const geometry::ImmersedDomain& domain) {
  std::set<int> faces;
  for (const geometry::BoundaryPoint& b : domain.boundary) faces.insert(b.face);
  geometry::CadTriangulation out;
  std::map<int, int> renumber;
  for (size_t t = 0; t < all.triangles.size(); ++t) {
    if (!faces.count(all.triangle_face[t])) continue;
    std::array<int, 3> tri{};
    for (int k = 0; k < 3; ++k) {
      const int old = all.triangles[t][k];
      auto [it, added] = renumber.emplace(old, static_cast<int>(out.points.size()));
      if (added) out.points.push_back(all.points[static_cast<size_t>(old)]);
      tri[k] = it->second;
    }
    out.triangles.push_back(tri);
    out.triangle_face.push_back(all.triangle_face[t]);
  }
  return out;
}

}  // namespace

geometry::CadTriangulation immersed_part_surface(const std::filesystem::path& part,
                                                 const geometry::ImmersedDomain& domain) {
  double cell = std::numeric_limits<double>::infinity();
  for (int d = 0; d < domain.background.param_dim(); ++d)
    cell = std::min(cell, domain.extent[d] / domain.background.knots(d).num_elements());
  return refine_triangulation(solid_surface(geometry::triangulate_cad(part, 1e-3), domain), cell);
}

}  // namespace isospring::workflows::detail
