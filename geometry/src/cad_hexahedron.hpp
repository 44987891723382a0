#pragma once
// Solids with hexahedral topology as one NURBS volume patch (transfinite interpolation).
#include <TopoDS_Shape.hxx>
#include <functional>
#include <string>

#include "isospring/nurbs/patch.hpp"

namespace isospring::geometry::detail {

/// A solid with 8 vertices, 12 edges and 6 faces of one wire and 4 edges each as the trivariate
/// Coons volume of its faces, each face the Coons patch of its (exactly converted, compatible)
/// edges. Planar faces with straight edges give the exact trilinear block. Accepted when every
/// face's Coons patch lies on the CAD face's surface, the Jacobian is positive and the volume
/// matches OCCT's to 1e-6. Corners are numbered right-handed with u, v, w most along x, y, z.
/// When a face is not the blend of its edges, the solid may still be a prism: two opposite faces
/// whose natural patches (from `natural_patch`, nullptr if none) are translates of each other give
/// the exact ruled (extruded) volume, accepted when the four side faces lie on the CAD faces and
/// the volume matches. Otherwise returns false and says why in `why`.
bool hexahedron_patch(const TopoDS_Shape& solid,
                      const std::function<const nurbs::Patch*(const TopoDS_Shape&)>& natural_patch,
                      nurbs::Patch& patch, std::string& why);

}  // namespace isospring::geometry::detail
