// A size check of the boundary quadrature before it allocates (immersed_cad_budget.hpp).
#include "immersed_cad_budget.hpp"

#include <BRepAdaptor_Surface.hxx>
#include <BRepTools.hxx>
#include <cmath>
#include <sstream>

#include "isospring/geometry/immersed_domain.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::geometry::detail {

double face_quadrature_bytes(const CadSolid::Shape& shape, size_t f, int order,
                             double piece_length) {
  // The face's size on the surface as face_quadrature measures it (its UV box's diagonal image).
  const TopoDS_Face& face = shape.faces[f];
  BRepAdaptor_Surface surface(face, true);
  double u0, u1, v0, v1;
  BRepTools::UVBounds(face, u0, u1, v0, v1);
  double length = 0.0;
  for (int k = 0; k < 8; ++k) {
    const double s = k / 8.0, t = (k + 1) / 8.0;
    length += surface.Value(u0 + s * (u1 - u0), v0 + s * (v1 - v0))
                  .Distance(surface.Value(u0 + t * (u1 - u0), v0 + t * (v1 - v0)));
  }
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
