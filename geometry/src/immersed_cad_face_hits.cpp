// A line against one trimmed face, classification by bins (immersed_cad_face_hits.hpp).
#include "immersed_cad_face_hits.hpp"

#include <BRepClass_FaceClassifier.hxx>
#include <BRepTools.hxx>
#include <BRep_Tool.hxx>
#include <BndLib_Add2dCurve.hxx>
#include <Bnd_Box2d.hxx>
#include <Geom2dAdaptor_Curve.hxx>
#include <GeomAPI_ProjectPointOnCurve.hxx>
#include <GeomAdaptor_Curve.hxx>
#include <Geom_Line.hxx>
#include <IntCurveSurface_HInter.hxx>
#include <IntCurveSurface_IntersectionPoint.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>

#include <algorithm>
#include <cmath>

namespace isospring::geometry::detail {

namespace {

// Bins per UV direction: fine enough that the bins a trimming curve passes through are a small
// share of a face with many holes; their states are found only when a hit lands in them.
constexpr int kBins = 256;
// Pieces each trimming curve is boxed in: a circle's pieces hug it, its whole box would not.
constexpr int kCurvePieces = 32;

bool is_analytic(GeomAbs_SurfaceType type) {
  return type == GeomAbs_Plane || type == GeomAbs_Cylinder || type == GeomAbs_Cone ||
         type == GeomAbs_Sphere || type == GeomAbs_Torus;
}

// The largest UV extent of a 3D tolerance on the surface (as IntCurvesFace's classifier
// tolerance), over the face's and its edges' tolerances.
double uv_tolerance(const TopoDS_Face& face, const BRepAdaptor_Surface& surface, double tolerance) {
  double tol3d = BRep_Tool::Tolerance(face);
  for (TopExp_Explorer e(face, TopAbs_EDGE); e.More(); e.Next())
    tol3d = std::max(tol3d, BRep_Tool::Tolerance(TopoDS::Edge(e.Current())));
  return std::max({surface.UResolution(tol3d), surface.VResolution(tol3d), tolerance});
}

// Is a closed-form distance clear of a classifier's tolerance? At the tolerance itself (a line
// placed exactly that far from an edge) OpenCascade's answer depends on its own rounding, so
// those points are left to it.
bool clear_of(double distance, double tolerance) {
  return std::abs(distance - tolerance) > 1e-6 * tolerance;
}

}  // namespace

FaceLineIntersector::FaceLineIntersector(const TopoDS_Face& face, double tolerance)
    : face_(face), full_intersector_(face, tolerance, true, true) {
  surface_ = new BRepAdaptor_Surface(face, true);
  const GeomAbs_SurfaceType type = surface_->GetType();
  const bool spline = type == GeomAbs_BSplineSurface || type == GeomAbs_BezierSurface;
  if (!is_analytic(type) && !spline) return;
  BRepTools::UVBounds(face, u0_, u1_, v0_, v1_);
  if (!(u1_ > u0_ && v1_ > v0_)) return;
  path_ = spline ? Path::kSpline : Path::kAnalytic;
  if (spline) {
    spline_ = std::make_unique<SplineLineHits>(*surface_, u0_, u1_, v0_, v1_);
    if (!spline_->usable()) {
      path_ = Path::kFull;
      return;
    }
  }
  const double uv_tol = uv_tolerance(face, *surface_, tolerance);
  classifier_ = std::make_unique<BRepTopAdaptor_FClass2d>(face, uv_tol);
  // IntCurvesFace's own classification of a hit: the smallest of the tolerances first.
  tolerance_3d_ = BRep_Tool::Tolerance(face);
  double smallest = tolerance_3d_;
  for (TopExp_Explorer e(face, TopAbs_EDGE); e.More(); e.Next()) {
    const double t = BRep_Tool::Tolerance(TopoDS::Edge(e.Current()));
    smallest = std::min(smallest, t);
    tolerance_3d_ = std::max(tolerance_3d_, t);
  }
  const double smallest_uv =
      std::max({surface_->UResolution(smallest), surface_->VResolution(smallest), tolerance});
  two_tolerances_ = uv_tol > smallest_uv;
  tight_classifier_ = std::make_unique<BRepTopAdaptor_FClass2d>(face, smallest_uv);
  tight_uv_ = smallest_uv;
  loose_uv_ = uv_tol;
  if (path_ == Path::kAnalytic) {
    planar_ = std::make_unique<PlanarFaceBoundary>(face);
    if (!planar_->usable()) planar_.reset();
  }
  nu_ = nv_ = kBins;
  bins_.assign(static_cast<size_t>(nu_) * static_cast<size_t>(nv_), Bin::kUnknown);
  mark_trimming_curves();
  if (path_ != Path::kFull) label_regions();
  std::vector<Bin>().swap(bins_);
}

// Connected regions of free bins (4-neighbours), by flood fill. No trimming curve meets a region,
// so the face's classifier answers the same everywhere in it. Past 65,535 regions the rest count
// as boundary bins (their lines take the full path: slower, never wrong).
void FaceLineIntersector::label_regions() {
  const size_t count = bins_.size();
  region_.assign(count, 0);
  region_state_.assign(1, Bin::kBoundary);
  std::vector<size_t> stack;
  for (size_t start = 0; start < count; ++start) {
    if (bins_[start] == Bin::kBoundary || region_[start] != 0) continue;
    if (region_state_.size() > 65535) break;
    const auto label = static_cast<std::uint16_t>(region_state_.size());
    region_state_.push_back(Bin::kUnknown);
    region_[start] = label;
    stack.assign(1, start);
    while (!stack.empty()) {
      const size_t bin = stack.back();
      stack.pop_back();
      const int i = static_cast<int>(bin % static_cast<size_t>(nu_));
      const int j = static_cast<int>(bin / static_cast<size_t>(nu_));
      const auto visit = [&](int ni, int nj) {
        if (ni < 0 || ni >= nu_ || nj < 0 || nj >= nv_) return;
        const size_t next =
            static_cast<size_t>(nj) * static_cast<size_t>(nu_) + static_cast<size_t>(ni);
        if (bins_[next] == Bin::kBoundary || region_[next] != 0) return;
        region_[next] = label;
        stack.push_back(next);
      };
      visit(i - 1, j);
      visit(i + 1, j);
      visit(i, j - 1);
      visit(i, j + 1);
    }
  }
}

// Every bin that a trimming curve's piece box (enlarged by twice the UV tolerance and a hair of
// the UV box) meets is a boundary bin: only there can the classifier's polygon or its exact
// fallback change its answer.
void FaceLineIntersector::mark_trimming_curves() {
  const double uv_tol = uv_tolerance(face_, *surface_, 0.0);
  const double margin = 2.0 * uv_tol + 1e-9 * std::max(u1_ - u0_, v1_ - v0_);
  const double du = (u1_ - u0_) / nu_, dv = (v1_ - v0_) / nv_;
  const auto clamp_u = [&](double u) {
    return std::clamp(static_cast<int>(std::floor((u - u0_) / du)), 0, nu_ - 1);
  };
  const auto clamp_v = [&](double v) {
    return std::clamp(static_cast<int>(std::floor((v - v0_) / dv)), 0, nv_ - 1);
  };
  const TopoDS_Face forward = TopoDS::Face(face_.Oriented(TopAbs_FORWARD));
  for (TopExp_Explorer e(forward, TopAbs_EDGE); e.More(); e.Next()) {
    double first = 0.0, last = 0.0;
    const Handle(Geom2d_Curve) curve =
        BRep_Tool::CurveOnSurface(TopoDS::Edge(e.Current()), forward, first, last);
    if (curve.IsNull() || !std::isfinite(first) || !std::isfinite(last)) {
      path_ = Path::kFull;  // no trimming curve to box: every line takes the full path
      return;
    }
    const Geom2dAdaptor_Curve adaptor(curve, first, last);
    for (int k = 0; k < kCurvePieces; ++k) {
      const double a = first + (last - first) * k / kCurvePieces;
      const double b = first + (last - first) * (k + 1) / kCurvePieces;
      Bnd_Box2d box;
      BndLib_Add2dCurve::Add(adaptor, a, b, 0.0, box);
      if (box.IsVoid()) continue;
      double x0, y0, x1, y1;
      box.Get(x0, y0, x1, y1);
      if (!(std::isfinite(x0) && std::isfinite(y0) && std::isfinite(x1) && std::isfinite(y1))) {
        path_ = Path::kFull;
        return;
      }
      if (x1 + margin < u0_ || x0 - margin > u1_ || y1 + margin < v0_ || y0 - margin > v1_)
        continue;
      for (int j = clamp_v(y0 - margin); j <= clamp_v(y1 + margin); ++j)
        for (int i = clamp_u(x0 - margin); i <= clamp_u(x1 + margin); ++i)
          bins_[static_cast<size_t>(j) * static_cast<size_t>(nu_) + static_cast<size_t>(i)] =
              Bin::kBoundary;
    }
  }
}

FaceLineIntersector::Bin FaceLineIntersector::bin_state(double u, double v) {
  const double su = (u - u0_) / (u1_ - u0_) * nu_, sv = (v - v0_) / (v1_ - v0_) * nv_;
  if (!(su >= 0.0 && su < nu_ && sv >= 0.0 && sv < nv_)) return Bin::kBoundary;
  const int i = static_cast<int>(su), j = static_cast<int>(sv);
  const std::uint16_t label =
      region_[static_cast<size_t>(j) * static_cast<size_t>(nu_) + static_cast<size_t>(i)];
  Bin& state = region_state_[label];
  if (state == Bin::kUnknown) {
    // The centre of the bin the hit is in: it lies in the region, away from every curve.
    const gp_Pnt2d centre(u0_ + (i + 0.5) * (u1_ - u0_) / nu_, v0_ + (j + 0.5) * (v1_ - v0_) / nv_);
    const TopAbs_State found = classifier_->Perform(centre);
    state = found == TopAbs_IN ? Bin::kIn : found == TopAbs_OUT ? Bin::kOut : Bin::kBoundary;
  }
  return state;
}

void FaceLineIntersector::perform_full(const gp_Lin& line, double w0, double w1,
                                       std::vector<FaceHit>& hits) {
  ++full_;
  full_intersector_.Perform(line, w0, w1);
  if (!full_intersector_.IsDone()) return;
  for (int i = 1; i <= full_intersector_.NbPnt(); ++i) {
    const IntCurveSurface_TransitionOnCurve transition = full_intersector_.Transition(i);
    FaceHit hit;
    hit.w = full_intersector_.WParameter(i);
    hit.net = transition == IntCurveSurface_In ? 1 : transition == IntCurveSurface_Out ? -1 : 0;
    hit.near_edge = full_intersector_.State(i) == TopAbs_ON;
    hit.u = full_intersector_.UParameter(i);
    hit.v = full_intersector_.VParameter(i);
    hits.push_back(hit);
  }
}

// The hits of the line with the face's untrimmed surface (over its UV box for B-splines), or
// false when they are left to IntCurvesFace_Intersector.
bool FaceLineIntersector::surface_hits(const gp_Lin& line, double w0, double w1) {
  surface_hits_.clear();
  if (path_ == Path::kSpline) return spline_->intersect(line, w0, w1, surface_hits_);
  // The surface intersection exactly as IntCurvesFace_Intersector does it for these surfaces.
  IntCurveSurface_HInter intersection;
  const Handle(GeomAdaptor_Curve) curve = new GeomAdaptor_Curve(new Geom_Line(line));
  intersection.Perform(curve, surface_);
  if (!intersection.IsDone()) return false;
  for (int i = 1; i <= intersection.NbPoints(); ++i) {
    const IntCurveSurface_IntersectionPoint& point = intersection.Point(i);
    if (point.W() < w0 || point.W() > w1) continue;
    // The transition as a signed cosine: In (against the normal) < 0 < Out; 0 a tangent.
    const double cosine = point.Transition() == IntCurveSurface_In    ? -1.0
                          : point.Transition() == IntCurveSurface_Out ? 1.0
                                                                      : 0.0;
    surface_hits_.push_back({point.U(), point.V(), point.W(), cosine});
  }
  return true;
}

// Is the hit on the face? IntCurvesFace_Intersector's test (with UseBToler): the point-in-face
// test with the smallest UV tolerance of the face and its edges; if that says OUT, the test with
// the largest, and if that says ON, ON only when an edge's 3D curve comes within the largest 3D
// tolerance. Classifiers are built once per face (IntCurvesFace builds the second one per line).
// On a planar face bounded by lines and circles the two classifiers' answers are found in closed
// form (ON within their tolerance of the nearest curve, else the side of it), unless the nearest
// point is a vertex.
TopAbs_State FaceLineIntersector::face_state(const SurfaceHit& hit, const gp_Lin& line) {
  const gp_Pnt2d uv(hit.u, hit.v);
  TopAbs_State state = TopAbs_UNKNOWN;
  PlanarFaceBoundary::Nearest nearest;
  if (planar_) nearest = planar_->nearest(uv);
  nearest.decided = nearest.decided && clear_of(nearest.distance, tight_uv_) &&
                    (!two_tolerances_ || clear_of(nearest.distance, loose_uv_));
  if (nearest.decided) {
    state = nearest.distance < tight_uv_ ? TopAbs_ON : nearest.inside ? TopAbs_IN : TopAbs_OUT;
  } else {
    ++classifier_calls_;
    state = tight_classifier_->Perform(uv);
  }
  if (state == TopAbs_OUT && two_tolerances_) {
    if (nearest.decided) {
      state = nearest.distance < loose_uv_ ? TopAbs_ON : TopAbs_OUT;
    } else {
      ++classifier_calls_;
      state = classifier_->Perform(uv);
    }
    if (state == TopAbs_ON) {
      state = TopAbs_OUT;
      const gp_Pnt point = line.Location().Translated(hit.w * gp_Vec(line.Direction()));
      for (TopExp_Explorer e(face_, TopAbs_EDGE); e.More() && state == TopAbs_OUT; e.Next()) {
        double first = 0.0, last = 0.0;
        const Handle(Geom_Curve) curve = BRep_Tool::Curve(TopoDS::Edge(e.Current()), first, last);
        if (curve.IsNull()) continue;  // a degenerate edge has no 3D curve
        GeomAPI_ProjectPointOnCurve projection(point, curve, first, last);
        if (projection.NbPoints() > 0 && projection.LowerDistance() <= tolerance_3d_)
          state = TopAbs_ON;
      }
    }
  }
  return state;
}

bool FaceLineIntersector::outside_strictly(double u, double v) {
  if (strict_uv_ == 0.0) {
    const BRepAdaptor_Surface surface(face_, true);
    double smallest = BRep_Tool::Tolerance(face_);
    for (TopExp_Explorer e(face_, TopAbs_EDGE); e.More(); e.Next())
      smallest = std::min(smallest, BRep_Tool::Tolerance(TopoDS::Edge(e.Current())));
    strict_uv_ = 1e-3 * std::max(surface.UResolution(smallest), surface.VResolution(smallest));
    if (!(strict_uv_ > 0.0)) strict_uv_ = 1e-300;
  }
  if (planar_) {
    const PlanarFaceBoundary::Nearest nearest = planar_->nearest(gp_Pnt2d(u, v));
    if (nearest.decided && clear_of(nearest.distance, strict_uv_))
      return nearest.distance >= strict_uv_ && !nearest.inside;
  }
  ++classifier_calls_;
  const TopoDS_Face forward = TopoDS::Face(face_.Oriented(TopAbs_FORWARD));
  const BRepClass_FaceClassifier exact(forward, gp_Pnt2d(u, v), strict_uv_);
  return exact.State() == TopAbs_OUT;
}

void FaceLineIntersector::perform(const gp_Lin& line, double w0, double w1,
                                  std::vector<FaceHit>& hits) {
  if (path_ == Path::kFull || !surface_hits(line, w0, w1)) return perform_full(line, w0, w1, hits);
  const bool reversed = face_.Orientation() == TopAbs_REVERSED;
  for (const SurfaceHit& point : surface_hits_) {
    const Bin state = bin_state(point.u, point.v);
    if (state == Bin::kOut) continue;
    const TopAbs_State exact = state == Bin::kBoundary ? face_state(point, line) : TopAbs_IN;
    if (exact != TopAbs_IN && exact != TopAbs_ON) continue;
    FaceHit hit;
    hit.w = point.w;
    hit.net = point.cosine < 0.0 ? 1 : point.cosine > 0.0 ? -1 : 0;
    if (reversed) hit.net = -hit.net;
    hit.near_edge = exact == TopAbs_ON;
    hit.u = point.u;
    hit.v = point.v;
    hits.push_back(hit);
  }
  ++fast_;
}

}  // namespace isospring::geometry::detail
