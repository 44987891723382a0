#pragma once
// Solids of full revolution with a four-sided profile as exact rational NURBS volumes.
#include <TopoDS_Shape.hxx>
#include <string>
#include <vector>

#include "isospring/nurbs/patch.hpp"

namespace isospring::geometry::detail {

/// A solid whose faces are all full (2 pi) surfaces of revolution about one axis (cylinders,
/// cones, spheres, tori, surfaces of revolution) or planes across the axis, with a four-sided
/// profile: four faces (e.g. a tube), three faces whose profile is closed by the axis (e.g. a
/// solid cylinder; the volume then has a collapsed face on the axis), or one face with a closed
/// meridian (a torus: the meridian is cut into four arcs, whose Coons patch is the single-patch
/// disk with a zero Jacobian at its four corners, as in the torus primitive). The profile (the
/// faces' meridians in one half-plane, exact B-splines; caps give radial segments) becomes a planar
/// Coons patch, revolved exactly with rational quarter arcs and split into four conforming 90
/// degree volume patches over [0, 1] (direction 0 around the axis). Accepted when every swept side
/// lies on a CAD face, the Jacobian is positive inside and the volume matches OCCT's to 1e-6;
/// otherwise returns false and says why.
bool revolution_patches(const TopoDS_Shape& solid, std::vector<nurbs::Patch>& patches,
                        std::string& why);

}  // namespace isospring::geometry::detail
