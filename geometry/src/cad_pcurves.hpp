#pragma once
// A face's trimming curves in its parameter space (pcurves) that stray from their edges' 3D
// curves, rebuilt at import.
//
// When a STEP file gives an edge only as a 3D curve, OpenCascade's reader computes the edge's
// pcurve on each face by approximation and checks the result against the 3D curve at 23
// parameters. A polynomial approximation of a rational curve can pass through the 3D curve at
// those very points and stray between them: on the CAx-IF GD&T block (top and bottom faces
// bilinear B-spline surfaces, trimmed by a circle given as three rational arcs) the pcurves lie
// up to 1.9e-5 m from the circle while the edges claim 1e-7 m, so the hole those faces leave is
// 6.4e-6 too large in area. Everything that trims a face by its pcurves sees that wrong face:
// OpenCascade's own area and volume (BRepGProp) and its point-in-face classification.
#include <TopoDS_Shape.hxx>

namespace isospring::geometry::detail {

/// For every (face, edge) of `shape` whose pcurve lies farther than twice the edge's tolerance
/// from the edge's 3D curve (sampled at 400 parameters), projects the 3D curve onto the face's
/// surface again (GeomProjLib::Curve2d) and keeps the new pcurve when it lies within the
/// tolerance; otherwise the original stays (then the 3D curve itself is off the surface, which a
/// new pcurve cannot mend). Seam edges and degenerate edges are left alone. Modifies the shape's
/// edges in place; returns how many pcurves were replaced.
int rebuild_stray_pcurves(const TopoDS_Shape& shape);

}  // namespace isospring::geometry::detail
