#pragma once
// Quadrature points on the faces of a solid, on their exact trimmed parametrisation (see
// immersed_cad.hpp for the method).
#include <string>
#include <vector>

#include "cad_solid_shape.hpp"
#include "isospring/geometry/immersed_domain.hpp"

namespace isospring::geometry::detail {

/// A face's size on its surface: the length of the image of its UV box's diagonal (eight chords).
/// face_quadrature cuts a face into pieces of about `piece_length` of it.
double face_surface_length(const TopoDS_Face& face);

/// Boundary points of every face of `shape`: `order` Gauss points per direction and piece, pieces
/// no longer than `piece_length` (m) on the surface, doubled until each face's area and first
/// moments repeat to 1e-9 (relative), at most twice. Faces that do not converge are named in
/// `warnings`. BoundaryPoint::face is the file's face index.
std::vector<BoundaryPoint> face_quadrature(const CadSolid::Shape& shape, int order,
                                           double piece_length, std::vector<std::string>& warnings);

}  // namespace isospring::geometry::detail
