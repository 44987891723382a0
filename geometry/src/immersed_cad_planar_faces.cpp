// Point-in-face in closed form for planar faces (immersed_cad_planar_faces.hpp).
#include "immersed_cad_planar_faces.hpp"

#include <BRepAdaptor_Surface.hxx>
#include <BRep_Tool.hxx>
#include <Geom2dAdaptor_Curve.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <gp_Circ2d.hxx>
#include <gp_Lin2d.hxx>

#include <algorithm>
#include <cmath>
#include <limits>

namespace isospring::geometry::detail {

PlanarFaceBoundary::PlanarFaceBoundary(const TopoDS_Face& face) {
  if (BRepAdaptor_Surface(face, false).GetType() != GeomAbs_Plane) return;
  const TopoDS_Face forward = TopoDS::Face(face.Oriented(TopAbs_FORWARD));
  for (TopExp_Explorer e(forward, TopAbs_EDGE); e.More(); e.Next()) {
    const TopoDS_Edge& edge = TopoDS::Edge(e.Current());
    if (BRep_Tool::Degenerated(edge)) return;
    double first = 0.0, last = 0.0;
    const Handle(Geom2d_Curve) pcurve = BRep_Tool::CurveOnSurface(edge, forward, first, last);
    if (pcurve.IsNull() || !std::isfinite(first) || !std::isfinite(last) || !(last > first)) return;
    const Geom2dAdaptor_Curve adaptor(pcurve, first, last);
    Curve c;
    c.first = first;
    c.last = last;
    c.reversed = edge.Orientation() == TopAbs_REVERSED;
    if (adaptor.GetType() == GeomAbs_Line) {
      const gp_Lin2d line = adaptor.Line();
      c.origin = line.Location();
      c.dx = line.Direction().X();
      c.dy = line.Direction().Y();
    } else if (adaptor.GetType() == GeomAbs_Circle) {
      const gp_Circ2d circle = adaptor.Circle();
      c.circle = true;
      c.origin = circle.Location();
      c.dx = circle.XAxis().Direction().X();
      c.dy = circle.XAxis().Direction().Y();
      c.yx = circle.YAxis().Direction().X();
      c.yy = circle.YAxis().Direction().Y();
      c.radius = circle.Radius();
      if (!(c.radius > 0.0) || last - first > 2.0 * M_PI + 1e-12) return;
    } else {
      return;  // another curve type: OpenCascade classifies
    }
    curves_.push_back(c);
  }
  usable_ = !curves_.empty();
}

PlanarFaceBoundary::Nearest PlanarFaceBoundary::nearest(const gp_Pnt2d& uv) const {
  Nearest best;
  best.distance = std::numeric_limits<double>::infinity();
  for (const Curve& c : curves_) {
    const double px = uv.X() - c.origin.X(), py = uv.Y() - c.origin.Y();
    double qx = 0.0, qy = 0.0, tx = 0.0, ty = 0.0;  // the nearest point and the tangent there
    bool at_end = false;  // the nearest point is an end of the edge (a vertex)
    if (!c.circle) {
      const double t = px * c.dx + py * c.dy;
      const double clamped = std::clamp(t, c.first, c.last);
      qx = clamped * c.dx;
      qy = clamped * c.dy;
      tx = c.dx;
      ty = c.dy;
      at_end = !(clamped > c.first && clamped < c.last);
    } else {
      // The angle of uv in the circle's frame, in [first, first + 2 pi).
      const double x = px * c.dx + py * c.dy, y = px * c.yx + py * c.yy;
      double angle = std::atan2(y, x);
      angle = c.first + std::fmod(std::fmod(angle - c.first, 2.0 * M_PI) + 2.0 * M_PI, 2.0 * M_PI);
      double at = angle;
      if (angle > c.last) {  // beyond the arc: the nearer of its ends
        const auto end_distance = [&](double a) {
          const double ex = c.radius * (std::cos(a) * c.dx + std::sin(a) * c.yx) - px;
          const double ey = c.radius * (std::cos(a) * c.dy + std::sin(a) * c.yy) - py;
          return std::hypot(ex, ey);
        };
        at = end_distance(c.first) <= end_distance(c.last) ? c.first : c.last;
      }
      qx = c.radius * (std::cos(at) * c.dx + std::sin(at) * c.yx);
      qy = c.radius * (std::cos(at) * c.dy + std::sin(at) * c.yy);
      tx = -std::sin(at) * c.dx + std::cos(at) * c.yx;
      ty = -std::sin(at) * c.dy + std::cos(at) * c.yy;
      at_end = !(at > c.first && at < c.last);
    }
    const double distance = std::hypot(px - qx, py - qy);
    if (distance >= best.distance) continue;
    best.distance = distance;
    // The nearest point at a curve's end is a vertex: the two curves there may disagree.
    best.decided = !at_end;
    // Left of the edge's direction in the face (against the curve's when reversed) is inside.
    const double cross = tx * (py - qy) - ty * (px - qx);
    best.inside = c.reversed ? cross < 0.0 : cross > 0.0;
  }
  if (!std::isfinite(best.distance)) best.decided = false;
  return best;
}

}  // namespace isospring::geometry::detail
