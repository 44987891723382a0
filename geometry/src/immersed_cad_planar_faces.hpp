// Point-in-face in closed form for a planar face whose trimming curves are lines and circles.
//
// Near a trimming curve OpenCascade's classifier (BRepTopAdaptor_FClass2d) cannot trust its
// polygon and falls back to the exact BRepClass_FaceClassifier, which intersects a probing line
// with every edge of the face: about 65,000 instructions a point on a plate's face with two holes,
// and the hits of lines through a cut cell at a hole's rim land there by the thousand. Both
// classifiers answer ON within the tolerance of an edge's curve in (u, v) and otherwise by the
// side the point is on; for lines and circles both are closed forms: the distance to the nearest
// curve and the side of it (the face lies to the left of its edges as oriented in the face).
// A plane's (u, v) are lengths, so the UV tolerance is the 3D one.
#pragma once

#include <TopoDS_Face.hxx>
#include <gp_Pnt2d.hxx>

#include <vector>

namespace isospring::geometry::detail {

class PlanarFaceBoundary {
 public:
  /// The face's trimming curves, when it is a plane bounded by lines and circles only;
  /// otherwise usable() is false.
  explicit PlanarFaceBoundary(const TopoDS_Face& face);
  bool usable() const { return usable_; }

  /// The distance from `uv` to the nearest trimming curve and whether `uv` lies on the face's
  /// side of it. `decided` is false when the nearest point is a curve's end (a vertex, where two
  /// curves' sides may disagree): the caller then asks OpenCascade.
  struct Nearest {
    double distance = 0.0;
    bool inside = false;
    bool decided = false;
  };
  Nearest nearest(const gp_Pnt2d& uv) const;

 private:
  struct Curve {
    bool circle = false;
    gp_Pnt2d origin;            // a line's point at parameter 0, a circle's centre
    double dx = 0.0, dy = 0.0;  // a line's unit direction; a circle's x axis
    double yx = 0.0, yy = 0.0;  // a circle's y axis (its sense gives the circle's direction)
    double radius = 0.0;
    double first = 0.0, last = 0.0;  // the edge's parameter range on the curve
    bool reversed = false;           // the edge runs against the curve in the face
  };
  std::vector<Curve> curves_;
  bool usable_ = false;
};

}  // namespace isospring::geometry::detail
