#pragma once
// Solids that are a planar face swept straight along its normal (plates with holes, extruded L
// sections) as volume patches: the face's patches extruded.
#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>
#include <functional>
#include <string>
#include <vector>

#include "isospring/nurbs/patch.hpp"

namespace isospring::geometry::detail {

/// The patches a face became (natural, Coons or cut), empty when it did not become patches.
using FacePatches = std::function<std::vector<nurbs::Patch>(const TopoDS_Face&)>;

/// When the solid is a prism of one of its planar faces (every vertex on that face's plane or on
/// one parallel plane at depth t, every other face either that opposite cap, with the same area,
/// or a plane/cylinder/extrusion containing the normal direction), the volume patches of the
/// face's patches extruded by t into the solid, right-handed, and `volume` (OpenCascade's) matched
/// to 1e-9. Otherwise false with `why`.
bool prism_patches(const TopoDS_Shape& solid, const FacePatches& face_patches, double volume,
                   std::vector<nurbs::Patch>& patches, std::string& why);

}  // namespace isospring::geometry::detail
