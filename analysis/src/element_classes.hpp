#pragma once
// Elements whose integrals are the same: on a patch whose geometry map is affine the element
// matrices depend only on the knots around each element, so a uniform 32^3 patch of degree 2 has
// 27 distinct stiffness matrices for its 32,768 elements, and assembly computes each once.
#include <vector>

#include "patch_quadrature.hpp"

namespace isospring::analysis::detail {

/// Whether x(u) = A u + b on the whole patch: equal weights (a polynomial map) and control points
/// at A times their Greville abscissae plus b, to 1e-12 of the net's extent (the Greville
/// abscissae reproduce linear functions exactly, so this is the affine map itself).
bool affine_patch(const nurbs::Patch& patch);

struct ElementClasses {
  std::vector<int> of_element;  // class of each element of the patch
  std::vector<int> first;       // an element of each class
};

/// Classes of elements of an affine patch with equal integrals: the same local knot differences
/// (the 2p knots that define the element's basis, less the element's start) in every direction,
/// to 1e-13 of the knot vector's length. Empty `of_element` when the patch is not affine.
ElementClasses affine_element_classes(const PatchQuadrature& quadrature);

}  // namespace isospring::analysis::detail
