// Axis-parallel lines against a solid's exact B-rep (immersed_cad_lines.hpp).
#include "immersed_cad_lines.hpp"

#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
#include <BRep_Tool.hxx>
#include <Precision.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <gp_Lin.hxx>
#include <gp_Pln.hxx>

#include <algorithm>
#include <optional>

#include "occt_box.hpp"

namespace isospring::geometry::detail {

namespace {

gp_Pnt to_gp(const Eigen::Vector3d& x) {
  return gp_Pnt(x.x(), x.y(), x.z());
}

}  // namespace

SolidProbe::SolidProbe(const CadSolid::Shape& shape)
    : shape_(shape), classifier_(shape.solid), edges_(shape) {
  const Corners box = tight_box(shape.solid);
  box_min_ = box.lo;
  box_max_ = box.hi;
  tighten_box();
  // Two faces report a crossing through their common edge each, within the edge's tolerance.
  double tolerance = 0.0;
  for (TopExp_Explorer e(shape.solid, TopAbs_EDGE); e.More(); e.Next())
    tolerance = std::max(tolerance, BRep_Tool::Tolerance(TopoDS::Edge(e.Current())));
  merge_ = std::max(4.0 * tolerance, 1e-10 * size());
  for (const TopoDS_Face& face : shape.faces) {
    const Corners face_box = tight_box(face);
    face_min_.push_back(face_box.lo - Eigen::Vector3d::Constant(merge_));
    face_max_.push_back(face_box.hi + Eigen::Vector3d::Constant(merge_));
    bounds_.emplace_back(face);
  }
  make_intersectors();
}

SolidProbe::SolidProbe(const SolidProbe& other)
    : shape_(other.shape_),
      face_min_(other.face_min_),
      face_max_(other.face_max_),
      bounds_(other.bounds_),
      box_min_(other.box_min_),
      box_max_(other.box_max_),
      merge_(other.merge_),
      classifier_(other.shape_.solid),
      edges_(other.edges_) {
  make_intersectors();
}

// Hits within the face's edge tolerance of its boundary count as on the face (IntCurvesFace's
// UseBToler).
void SolidProbe::make_intersectors() {
  for (const TopoDS_Face& face : shape_.faces)
    intersectors_.push_back(std::make_unique<FaceLineIntersector>(face, 1e-9));
}

long SolidProbe::fast_face_lines() const {
  long n = 0;
  for (const auto& intersector : intersectors_) n += intersector->fast_lines();
  return n;
}

long SolidProbe::face_classifications() const {
  long n = 0;
  for (const auto& intersector : intersectors_) n += intersector->classifier_calls();
  return n;
}

long SolidProbe::full_face_lines() const {
  long n = 0;
  for (const auto& intersector : intersectors_) n += intersector->full_lines();
  return n;
}

// OpenCascade's optimal box is Precision::Confusion() (1e-7 m) too large on a side it finds by
// numerical extrema (curved or spline faces). A grid on it would have the part's extreme faces
// 1e-7 m inside its boundary planes, where lines along them lie within the faces' tolerance and
// are ambiguous. Each side is moved onto the part by the exact distance between the side's
// plane and the faces near it.
void SolidProbe::tighten_box() {
  // Faces within a few confusions of a side are candidates: the enlargement is absolute, so a
  // slack relative to the part alone missed it on parts under 0.1 m.
  const double slack = std::max(1e-6 * size(), 10.0 * Precision::Confusion());
  const double extent = 10.0 * size();
  for (int k = 0; k < 3; ++k)
    for (const bool upper : {false, true}) {
      const double bound = upper ? box_max_[k] : box_min_[k];
      Eigen::Vector3d origin = 0.5 * (box_min_ + box_max_), normal = Eigen::Vector3d::Zero();
      origin[k] = bound;
      normal[k] = 1.0;
      const TopoDS_Face plane =
          BRepBuilderAPI_MakeFace(gp_Pln(to_gp(origin), gp_Dir(normal.x(), normal.y(), normal.z())),
                                  -extent, extent, -extent, extent);
      double nearest = slack;
      for (const TopoDS_Face& face : shape_.faces) {
        const Corners face_box = tight_box(face);
        const double side = upper ? face_box.hi[k] : face_box.lo[k];
        if (std::abs(side - bound) > slack) continue;
        BRepExtrema_DistShapeShape distance(plane, face, Extrema_ExtFlag_MIN);
        if (distance.IsDone()) nearest = std::min(nearest, distance.Value());
      }
      if (nearest < slack) (upper ? box_max_[k] : box_min_[k]) += upper ? -nearest : nearest;
    }
}

std::vector<SolidProbe::Event> SolidProbe::events(const Eigen::Vector3d& point, int axis) {
  ++lines_;
  Eigen::Vector3d origin = point;
  origin[axis] = 0.0;
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();
  direction[axis] = 1.0;
  const gp_Lin line(to_gp(origin), gp_Dir(direction.x(), direction.y(), direction.z()));
  const double w0 = box_min_[axis] - 1e-3 * size(), w1 = box_max_[axis] + 1e-3 * size();
  const int a = (axis + 1) % 3, b = (axis + 2) % 3;
  hits_.clear();
  for (size_t f = 0; f < intersectors_.size(); ++f) {
    if (point[a] < face_min_[f][a] || point[a] > face_max_[f][a] || point[b] < face_min_[f][b] ||
        point[b] > face_max_[f][b])
      continue;
    const size_t first = hits_.size();
    intersectors_[f]->perform(line, w0, w1, hits_);
    for (size_t k = first; k < hits_.size(); ++k) hits_[k].face = static_cast<int>(f);
  }
  std::sort(hits_.begin(), hits_.end(),
            [](const FaceHit& x, const FaceHit& y) { return x.w < y.w; });
  // One crossing through an edge or vertex is reported by every face that meets there.
  std::vector<Event> merged;
  size_t group_start = 0;
  const auto close_group = [&](size_t end) {
    // A hit only near its face's edge that no other face reports is not a crossing through the
    // edge: the line passes beside the face, within the tolerance of its edge, where the
    // neighbouring face runs along the line. It counts only if it is on the face strictly.
    if (end - group_start == 1 && hits_[group_start].near_edge) {
      const FaceHit& hit = hits_[group_start];
      if (intersectors_[static_cast<size_t>(hit.face)]->outside_strictly(hit.u, hit.v))
        merged.pop_back();
    }
  };
  for (size_t k = 0; k < hits_.size(); ++k) {
    const FaceHit& hit = hits_[k];
    if (!merged.empty() && hit.w - merged.back().t <= merge_) {
      merged.back().net += hit.net;
    } else {
      if (!merged.empty()) close_group(k);
      group_start = k;
      merged.push_back({hit.w, hit.net});
    }
  }
  if (!merged.empty()) close_group(hits_.size());
  return merged;
}

std::vector<Interval> SolidProbe::classify_pieces(const Eigen::Vector3d& point, int axis,
                                                  const std::vector<Event>& events, double lo,
                                                  double hi) {
  ++classified_;
  std::vector<Interval> inside;
  for (size_t k = 0; k + 1 < events.size(); ++k) {
    // Only the pieces that overlap [lo, hi] survive the caller's clipping; the classifier is
    // the expensive part of a line (a profile of a holed plate put half of its cut cells' time
    // in it when every piece of a 200 mm line was classified for a 10 mm cell).
    if (events[k + 1].t <= lo || events[k].t >= hi) continue;
    Eigen::Vector3d middle = point;
    middle[axis] = 0.5 * (events[k].t + events[k + 1].t);
    if (!contains(middle)) continue;
    if (!inside.empty() && inside.back().hi == events[k].t)
      inside.back().hi = events[k + 1].t;
    else
      inside.push_back({events[k].t, events[k + 1].t});
  }
  return inside;
}

std::vector<Interval> SolidProbe::inside(const Eigen::Vector3d& point, int axis, double lo,
                                         double hi) {
  const std::vector<Event> found = events(point, axis);
  std::vector<Interval> whole;
  bool in = false, consistent = true;
  double start = 0.0;
  for (const Event& e : found) {
    if (e.net > 0) {
      if (in) consistent = false;
      in = true;
      start = e.t;
    } else if (e.net < 0) {
      if (!in)
        consistent = false;
      else
        whole.push_back({start, e.t});
      in = false;
    }
  }
  if (in) consistent = false;
  if (!consistent) whole = classify_pieces(point, axis, found, lo, hi);
  std::vector<Interval> clipped;
  for (const Interval& piece : whole) {
    const double a = std::max(piece.lo, lo), b = std::min(piece.hi, hi);
    if (b > a) clipped.push_back({a, b});
  }
  return clipped;
}

std::vector<double> SolidProbe::crossings(const Eigen::Vector3d& point, int axis, double lo,
                                          double hi) {
  std::vector<double> found;
  for (const Event& e : events(point, axis))
    if (e.t > lo && e.t < hi) found.push_back(e.t);
  return found;
}

bool SolidProbe::near_boundary(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  const Eigen::Vector3d centre = 0.5 * (lo + hi);
  const double radius = 0.5 * (hi - lo).norm() + merge_;
  std::optional<TopoDS_Vertex> vertex;  // made when a face needs OpenCascade's distance
  for (size_t f = 0; f < shape_.faces.size(); ++f) {
    if ((face_min_[f].array() > hi.array()).any() || (face_max_[f].array() < lo.array()).any())
      continue;
    if (const SplineLineHits* spline = intersectors_[f]->spline()) {
      // The convex hulls of its Bezier pieces bound a B-spline face (see may_meet).
      const Eigen::Vector3d margin = Eigen::Vector3d::Constant(merge_);
      if (spline->may_meet(lo - margin, hi + margin)) return true;
      continue;
    }
    if (bounds_[f].distance_below(centre) > radius) continue;
    if (!vertex) vertex = BRepBuilderAPI_MakeVertex(to_gp(centre));
    ++distances_;
    BRepExtrema_DistShapeShape distance(*vertex, shape_.faces[f], Extrema_ExtFlag_MIN);
    if (!distance.IsDone() || distance.Value() <= radius) return true;
  }
  return false;
}

bool SolidProbe::contains(const Eigen::Vector3d& point) {
  classifier_.Perform(to_gp(point), std::max(1e-9 * size(), 1e-12));
  return classifier_.State() == TopAbs_IN;
}

}  // namespace isospring::geometry::detail
