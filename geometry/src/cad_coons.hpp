#pragma once
// Trimmed CAD faces with four boundary edges as Coons patches of their edges.
#include <TopoDS_Face.hxx>

#include "isospring/geometry/cad.hpp"

namespace isospring::geometry::detail {

/// Number of oriented edges of the face's outer wire (a seam counts twice).
int outer_wire_edges(const TopoDS_Face& face);

/// The Coons patch of a one-wire, four-edge face: the edge curves converted exactly to B-splines
/// (in metres), taken around the wire in the face's orientation (so dX/du x dX/dv is the face's
/// outward normal). Accepted only when the patch lies on the face's surface (interior samples
/// projected onto it: within the edge tolerance or 1e-9 of the face size), its Jacobian has the
/// face's orientation at every sample, and its area matches OCCT's face area to 1e-6. Otherwise
/// returns false with `report.note` saying why and what to do. Sets report.coons and
/// report.coons_deviation on success.
bool coons_face_patch(const TopoDS_Face& face, CadFace& report, nurbs::Patch& patch);

}  // namespace isospring::geometry::detail
