#pragma once
// Trimmed CAD faces with four boundary edges as Coons patches of their edges.
#include <Geom_Curve.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>

#include "isospring/geometry/cad.hpp"

namespace isospring::geometry::detail {

/// A curve between two of its parameters as a clamped NURBS curve (exact B-spline conversion).
/// Throws std::runtime_error when the conversion does not reproduce it.
nurbs::Patch curve_patch(const Handle(Geom_Curve) & curve, double first, double last);

/// The edge's 3D curve as a clamped NURBS curve (exact B-spline conversion, location applied),
/// from its first to its last parameter, reversed when the edge is REVERSED. Throws
/// std::runtime_error when there is no 3D curve or the conversion does not reproduce it.
nurbs::Patch edge_curve(const TopoDS_Edge& edge);

/// Largest distance from the face's surface of samples of a surface patch (an 8 x 8 interior grid
/// projected onto the surface). Throws std::runtime_error when a sample cannot be projected.
double surface_deviation(const nurbs::Patch& patch, const TopoDS_Face& face);

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
