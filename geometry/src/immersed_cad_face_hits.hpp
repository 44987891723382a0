#pragma once
// Where a line meets one trimmed face of a B-rep: OpenCascade's IntCurvesFace_Intersector, made
// fast for analytic and B-spline faces without changing its answer.
//
// IntCurvesFace_Intersector intersects the line with the face's untrimmed surface
// (IntCurveSurface_HInter, in closed form for planes, cylinders, cones, spheres and tori) and then
// classifies every hit's (u, v) against the face's trimming curves (BRepTopAdaptor_FClass2d, a
// point-in-polygon test over all the face's edges, exact near them). On a face with many holes the
// classification is nearly all of the cost. Here the face's UV box is cut into bins; a bin that
// no trimming curve comes near (the curves' bounding boxes, piece by piece, enlarged by the edges'
// UV tolerance) lies wholly inside or wholly outside the face, so its state is that of its centre,
// classified once by the same classifier. A hit in any other bin (near a trimming curve, or
// outside the UV box) is classified as IntCurvesFace_Intersector classifies it (the same two
// classifiers and edge test, built once per face instead of once per line), so on these faces
// the answer is IntCurvesFace's bit for bit. Bins that touch (share a side) and are both free of
// trimming curves have the same state, so the free bins are grouped into connected regions and
// one centre per region is classified, the first time a hit lands in it.
//
// On B-spline and Bezier faces IntCurvesFace's surface intersection is a polyhedral pre-search
// that costs more than the classification; there the untrimmed hits come from Bezier subdivision
// and Newton's method (immersed_cad_spline_hits.hpp), the same to round-off, and a line it cannot
// certify goes to IntCurvesFace_Intersector itself, as does every line on other faces.
#include <BRepAdaptor_Surface.hxx>
#include <BRepTopAdaptor_FClass2d.hxx>
#include <IntCurvesFace_Intersector.hxx>
#include <TopoDS_Face.hxx>
#include <gp_Lin.hxx>

#include <cstdint>
#include <memory>
#include <vector>

#include "immersed_cad_planar_faces.hpp"
#include "immersed_cad_spline_hits.hpp"

namespace isospring::geometry::detail {

struct FaceHit {
  double w = 0.0;  // line parameter
  int net = 0;     // +1 the line enters the solid, -1 it leaves, 0 a touch (tangent)
  // On the face only within the edges' tolerance (the classifier said ON, not IN): such a hit
  // is a crossing through an edge when another face reports it too, else see
  // FaceLineIntersector::outside_strictly.
  bool near_edge = false;
  double u = 0.0, v = 0.0;  // on the face's surface
  int face = 0;             // set by the caller
};

class FaceLineIntersector {
 public:
  /// `tolerance` and the use of the edges' tolerance as IntCurvesFace_Intersector's.
  FaceLineIntersector(const TopoDS_Face& face, double tolerance);

  /// Appends the hits of `line` with the face with parameter in [w0, w1] (IntCurvesFace's
  /// points whose classification is IN or ON, with the transition seen from the solid).
  void perform(const gp_Lin& line, double w0, double w1, std::vector<FaceHit>& hits);

  /// Is a near-edge hit at (u, v) outside the face's trimmed region by more than 1e-3 of the
  /// edges' tolerance (OpenCascade's exact face classifier)? A line that runs beside a face
  /// parallel to it (a cylinder's wall along the line) meets only the neighbouring face near
  /// their edge; counted on that face within the tolerance, all such lines would add a band as
  /// wide as the tolerance to the part (on the CAx-IF bolt's head, 1e-7 m along its rim).
  bool outside_strictly(double u, double v);

  /// Lines answered without IntCurvesFace's classification so far, and lines sent to it.
  long fast_lines() const { return fast_; }
  /// The B-spline path's surface (null on other faces).
  const SplineLineHits* spline() const { return path_ == Path::kSpline ? spline_.get() : nullptr; }
  long full_lines() const { return full_; }
  /// Hits near a trimming curve classified by OpenCascade (the rest of them, on planar faces
  /// bounded by lines and circles, in closed form: immersed_cad_planar_faces.hpp).
  long classifier_calls() const { return classifier_calls_; }

 private:
  enum class Bin : unsigned char { kUnknown, kIn, kOut, kBoundary };
  enum class Path : unsigned char { kFull, kAnalytic, kSpline };
  void mark_trimming_curves();
  void label_regions();
  Bin bin_state(double u, double v);
  void perform_full(const gp_Lin& line, double w0, double w1, std::vector<FaceHit>& hits);
  bool surface_hits(const gp_Lin& line, double w0, double w1);
  TopAbs_State face_state(const SurfaceHit& hit, const gp_Lin& line);

  TopoDS_Face face_;
  IntCurvesFace_Intersector full_intersector_;
  Path path_ = Path::kFull;
  Handle(BRepAdaptor_Surface) surface_;
  std::unique_ptr<SplineLineHits> spline_;               // on B-spline and Bezier faces
  std::vector<SurfaceHit> surface_hits_;                 // of the current line (reused memory)
  std::unique_ptr<BRepTopAdaptor_FClass2d> classifier_;  // bin centres; the largest tolerance
  std::unique_ptr<BRepTopAdaptor_FClass2d> tight_classifier_;  // the smallest tolerance
  bool two_tolerances_ = false;  // the largest UV tolerance exceeds the smallest
  double tolerance_3d_ = 0.0;    // the largest of the face's and its edges'
  double u0_ = 0.0, u1_ = 0.0, v0_ = 0.0, v1_ = 0.0;
  int nu_ = 0, nv_ = 0;
  std::vector<Bin> bins_;              // kBoundary or kUnknown (free) per bin, while labelling
  std::vector<std::uint16_t> region_;  // per bin: 0 on a trimming curve, else its free region
  std::vector<Bin> region_state_;      // per region (index 0 unused)
  std::unique_ptr<PlanarFaceBoundary> planar_;  // when the face is planar, lines and circles
  double tight_uv_ = 0.0, loose_uv_ = 0.0;      // the two classifiers' UV tolerances
  long fast_ = 0, full_ = 0, classifier_calls_ = 0;
  double strict_uv_ = 0.0;  // the strict test's UV tolerance (1e-3 of the smallest edge's)
};

}  // namespace isospring::geometry::detail
