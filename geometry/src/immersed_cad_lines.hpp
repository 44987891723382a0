#pragma once
// Axis-parallel lines against the exact B-rep of a solid: where they cross its boundary and where
// they are inside (OpenCascade's IntCurvesFace_Intersector per face, faces culled by their
// bounding boxes, hits on analytic faces classified by bins: immersed_cad_face_hits.hpp), and
// OpenCascade's classifier and face distances for points and boxes. A probe is used by one thread
// at a time; a copy made by SolidProbe(const SolidProbe&) shares nothing mutable with its source.
#include <BRepClass3d_SolidClassifier.hxx>

#include <Eigen/Core>
#include <memory>
#include <utility>
#include <vector>

#include "cad_solid_shape.hpp"
#include "immersed_cad_edges.hpp"
#include "immersed_cad_face_bounds.hpp"
#include "immersed_cad_face_hits.hpp"

namespace isospring::geometry::detail {

struct Interval {
  double lo = 0.0, hi = 0.0;
};

class SolidProbe {
 public:
  explicit SolidProbe(const CadSolid::Shape& shape);
  /// A probe for another thread: the same boxes, its own intersectors and classifier, counters
  /// at zero.
  SolidProbe(const SolidProbe& other);
  SolidProbe& operator=(const SolidProbe&) = delete;

  /// Where the line through `point` along `axis` is inside the solid, as intervals of the axis
  /// coordinate clipped to [lo, hi]. The whole line is intersected, so whether it starts inside
  /// is known; crossings are merged within the edges' tolerance and their transitions (in or
  /// out of the part) must alternate, else the pieces between them are classified.
  std::vector<Interval> inside(const Eigen::Vector3d& point, int axis, double lo, double hi);

  /// Axis coordinates in (lo, hi) where that line meets the boundary (crossings and touches).
  std::vector<double> crossings(const Eigen::Vector3d& point, int axis, double lo, double hi);

  /// Could a face meet the box [lo, hi]? (A face whose bounding box meets it and whose exact
  /// distance from the box centre is within the half-diagonal, unless its analytic surface
  /// already puts it farther (immersed_cad_face_bounds.hpp); a B-spline face whose Bezier pieces'
  /// hulls meet it, as OpenCascade's distance to such a face can miss its interior;
  /// conservative.)
  bool near_boundary(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi);

  /// Where the solid's edges cross boxes and planes (this probe's own evaluators).
  EdgeCrossings& edges() { return edges_; }

  /// Is the point inside the solid (OpenCascade's classifier)?
  bool contains(const Eigen::Vector3d& point);

  Eigen::Vector3d box_min() const { return box_min_; }
  Eigen::Vector3d box_max() const { return box_max_; }
  double size() const { return (box_max_ - box_min_).norm(); }
  /// Crossings closer than this along a line are one (the edges' tolerance, at least 1e-10 of
  /// the size); a line that close to a face parallel to it is ambiguous.
  double merge_distance() const { return merge_; }
  long lines() const { return lines_; }                  // lines intersected so far
  long classified_lines() const { return classified_; }  // of which needed the classifier
  long distance_queries() const { return distances_; }
  /// Line-face intersections answered by the bins / by IntCurvesFace's own classification.
  long fast_face_lines() const;
  long full_face_lines() const;
  /// Hits near a trimming curve that OpenCascade's point-in-face classifiers were asked about.
  long face_classifications() const;

 private:
  struct Event {
    double t = 0.0;
    int net = 0;  // entries minus exits of the part at this crossing (0: a touch)
  };
  std::vector<Event> events(const Eigen::Vector3d& point, int axis);
  void tighten_box();
  void make_intersectors();
  // The pieces between `events` that overlap [lo, hi], classified at their midpoints.
  std::vector<Interval> classify_pieces(const Eigen::Vector3d& point, int axis,
                                        const std::vector<Event>& events, double lo, double hi);

  const CadSolid::Shape& shape_;
  std::vector<std::unique_ptr<FaceLineIntersector>> intersectors_;
  std::vector<Eigen::Vector3d> face_min_, face_max_;  // bounding boxes, enlarged by tolerance
  std::vector<FaceSurfaceBound> bounds_;              // per face (immersed_cad_face_bounds.hpp)
  Eigen::Vector3d box_min_, box_max_;                 // of the solid (exact, optimal)
  double merge_ = 0.0;  // crossings closer than this along a line are one
  BRepClass3d_SolidClassifier classifier_;
  EdgeCrossings edges_;
  long lines_ = 0, classified_ = 0, distances_ = 0;
  std::vector<FaceHit> hits_;  // of the current line (kept to reuse its memory)
};

}  // namespace isospring::geometry::detail
