// A size check of the boundary quadrature before it allocates (immersed_cad_budget.hpp).
#include "immersed_cad_budget.hpp"

#include "immersed_cad_faces.hpp"

#include <cmath>
#include <sstream>

#include "isospring/geometry/immersed_domain.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::geometry::detail {

double face_quadrature_bytes(const CadSolid::Shape& shape, size_t f, int order,
                             double piece_length) {
  // The face's size on the surface as face_quadrature measures it.
  const double length = face_surface_length(shape.faces[f]);
  const double pieces = std::max(1.0, std::ceil(length / piece_length));
  return 5.0 * pieces * pieces * order * order * static_cast<double>(sizeof(BoundaryPoint));
}

void check_face_quadrature_size(const CadSolid::Shape& shape, int order, double piece_length,
                                double limit_bytes, const std::string& name) {
  double total = 0.0, largest = 0.0;
  size_t worst = 0;
  for (size_t f = 0; f < shape.faces.size(); ++f) {
    const double bytes = face_quadrature_bytes(shape, f, order, piece_length);
    total += bytes;
    if (bytes > largest) largest = bytes, worst = f;
  }
  if (total <= limit_bytes) return;
  std::ostringstream out;
  out.precision(3);
  out << name << ": the boundary quadrature would take at least " << total / 1e9 << " GB (limit "
      << limit_bytes / 1e9 << " GB, immersion option max_quadrature_gb), " << largest / 1e9
      << " GB of it on face " << shape.face_index[worst]
      << ": its pieces follow the grid's thinnest cell, " << piece_length
      << " m. Give a larger cell_size or fewer cells, a larger grading 'smallest', or leave out "
         "breaks (keep_planar_faces) that lie close to each other";
  throw nurbs::InputError(out.str());
}

}  // namespace isospring::geometry::detail
