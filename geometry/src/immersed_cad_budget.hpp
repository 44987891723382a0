#pragma once
// A size check of the boundary quadrature before it allocates (immersed_cad_faces.hpp).
#include <string>

#include "cad_solid_shape.hpp"

namespace isospring::geometry::detail {

/// Bytes of boundary points that face_quadrature's first two rules (pieces and twice as many)
/// of face `f` of `shape` take at least: its pieces follow `piece_length` (the grid's thinnest
/// cell), so a face of length L gets about (L / piece_length)^2 (1 + 4) order^2 points.
double face_quadrature_bytes(const CadSolid::Shape& shape, size_t f, int order,
                             double piece_length);

/// Throws nurbs::InputError when the boundary quadrature of all faces would take more than
/// `limit_bytes` (naming the largest face, the thinnest cell and the options that fix it),
/// before anything is allocated. `name` is the part's.
void check_face_quadrature_size(const CadSolid::Shape& shape, int order, double piece_length,
                                double limit_bytes, const std::string& name);

}  // namespace isospring::geometry::detail
