#pragma once
// Planar CAD faces with holes or other than four edges, cut into conforming four-sided patches.
#include <TopoDS_Face.hxx>
#include <vector>

#include "isospring/geometry/cad.hpp"

namespace isospring::geometry::detail {

/// The planar face as conforming patches (planar_split.hpp) whose boundaries are the exact
/// B-spline conversions of its edge curves (in metres) plus straight cut lines, oriented so that
/// dX/du x dX/dv is the face's outward normal. Accepted only when every patch's Jacobian is
/// positive (sampled at 6 x 6 points per element, in the face's plane) and the patches' area
/// matches OpenCascade's face area to 1e-9. Sets report.split and the Jacobian bounds on
/// success; otherwise returns false with report.note saying why and what to do.
bool split_planar_face(const TopoDS_Face& face, CadFace& report,
                       std::vector<nurbs::Patch>& patches);

}  // namespace isospring::geometry::detail
