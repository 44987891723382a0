#pragma once
// Where a line meets a B-spline (or Bezier) surface over a face's UV box, without OpenCascade's
// polyhedral pre-search (IntCurveSurface_HInter on a 20-40 sample polyhedron per face, which on
// freeform parts was nearly all of the immersion's time).
//
// The surface, restricted to the UV box, is cut into its Bezier patches (knot insertion,
// GeomConvert_BSplineSurfaceToBezierSurface). For a line p + w d, with e1, e2 spanning the plane
// normal to d, the hits are the zeros of the polynomial map
//   G(u, v) = (e1 . (X(u, v) - p W(u, v)), e2 . (X(u, v) - p W(u, v)))
// (X the weighted poles, W the weights: rational surfaces too, as W > 0). G is a Bezier map whose
// control points are those of the poles, so a patch whose net's box excludes 0 has no hit; other
// patches are halved in u and v (de Casteljau) until the net certifies that G is injective on the
// piece: its Jacobian J(x) is a convex combination of the net's difference vectors, column by
// column, and when every J0^-1 J(x) lies within 1/2 of the identity (J0 the mean differences) the
// piece holds at most one zero, which Newton's method on the exact surface (OpenCascade's D1)
// finds from the piece's centre. A piece that reaches the depth limit uncertified (a silhouette
// of the surface seen along d, a degenerate patch edge), a Newton iteration that does not
// converge, or a hit at a grazing angle makes the whole query fail: the caller then asks
// IntCurvesFace_Intersector itself, so doubtful lines keep OpenCascade's answer.
#include <BRepAdaptor_Surface.hxx>
#include <gp_Lin.hxx>

#include <Eigen/Core>
#include <vector>

namespace isospring::geometry::detail {

struct SurfaceHit {
  double u = 0.0, v = 0.0, w = 0.0;
  double cosine = 0.0;  // between the surface normal S_u x S_v and the line direction
};

class SplineLineHits {
 public:
  /// The B-spline or Bezier surface of `surface` over [u0, u1] x [v0, v1]; usable() is false for
  /// other surfaces and for a box the surface does not cover.
  SplineLineHits(const BRepAdaptor_Surface& surface, double u0, double u1, double v0, double v1);

  bool usable() const { return !patches_.empty(); }

  /// Appends every hit of `line` with w in [w0, w1]. Returns false (hits unusable) when a hit
  /// could not be certified; see the file comment.
  bool intersect(const gp_Lin& line, double w0, double w1, std::vector<SurfaceHit>& hits) const;

  /// Could the surface (over the UV box) meet the box [lo, hi]? Conservative: the surface lies in
  /// the union of the boxes of its patches' nets, each patch halved three times in u and v.
  /// (OpenCascade's point-face distance, which the classification uses on other faces, can
  /// return the distance to the face's edges when the projection onto a B-spline face fails.)
  bool may_meet(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) const;

 private:
  struct Patch {
    int nu = 0, nv = 0;                     // poles per direction (degree + 1)
    double ua = 0, ub = 0, va = 0, vb = 0;  // its piece of the surface's parameters
    std::vector<Eigen::Vector4d> poles;     // (w x, w y, w z, w), index i + nu j
    Eigen::Vector3d lo, hi;                 // box of the poles (the patch lies in it)
  };
  struct Piece {
    double s0, s1, t0, t1;  // in the patch's [0, 1]^2
  };
  bool search(const Patch& patch, const std::vector<Eigen::Vector2d>& net, const Piece& piece,
              int depth, const gp_Lin& line, std::vector<SurfaceHit>& found) const;
  bool newton(const Patch& patch, const Piece& piece, const gp_Lin& line,
              std::vector<SurfaceHit>& found) const;

  void add_piece_boxes(const std::vector<Eigen::Vector4d>& net, int nu, int nv, int depth);

  BRepAdaptor_Surface surface_;
  std::vector<Patch> patches_;
  std::vector<Eigen::Vector3d> piece_lo_, piece_hi_;  // boxes of the halved patches
  double scale_ = 1.0;                                // the surface's box diagonal
};

}  // namespace isospring::geometry::detail
