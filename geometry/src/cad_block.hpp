#pragma once
// Orthogonal solids with straight through-holes (L-brackets, stepped blocks with bores) as
// hexahedral volume patches: block_split.hpp on the solid's faces.
#include <TopoDS_Shape.hxx>
#include <string>
#include <vector>

#include "isospring/nurbs/patch.hpp"

namespace isospring::geometry::detail {

/// When every planar face of the solid is normal to one of three orthogonal axes, every other
/// face is the wall of a straight hole along one of them, and each hole runs from an inner wire
/// of one face to an inner wire of a parallel face, the solid's conforming volume patches
/// (split_block_region) with positive Jacobians (sampled 4 per element and direction) and
/// `volume` (OpenCascade's) matched to 1e-9, or to within what the file's holes disagree
/// between their two ends times their length (then `remark` says so; otherwise it is empty). A
/// hole whose wall is a cylinder is built from the cylinder, exactly. Otherwise false with `why`.
bool block_patches(const TopoDS_Shape& solid, double volume, std::vector<nurbs::Patch>& patches,
                   std::string& why, std::string& remark);

}  // namespace isospring::geometry::detail
