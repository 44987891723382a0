#pragma once
// Solids of full revolution with a four-sided profile as exact rational NURBS volumes.
#include <TopoDS_Shape.hxx>
#include <string>
#include <vector>

#include "isospring/nurbs/patch.hpp"

namespace isospring::geometry::detail {

/// A solid whose faces are all full (2 pi) surfaces of revolution about one axis (cylinders,
/// cones, spheres, tori, surfaces of revolution) or planes across the axis, with four faces (a
/// four-sided profile that does not touch the axis, e.g. a tube): the profile (the faces'
/// meridians in one half-plane, exact B-splines; caps give radial segments) becomes a planar Coons
/// patch, revolved exactly with rational quarter arcs and split into four conforming 90 degree
/// volume patches (direction 0 around the axis). Accepted when every boundary face lies on a CAD
/// face, the Jacobian is positive and the volume matches OCCT's to 1e-6; otherwise returns false
/// and says why.
bool revolution_patches(const TopoDS_Shape& solid, std::vector<nurbs::Patch>& patches,
                        std::string& why);

}  // namespace isospring::geometry::detail
