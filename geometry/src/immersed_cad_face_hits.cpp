// A line against one trimmed face, classification by bins (immersed_cad_face_hits.hpp).
#include "immersed_cad_face_hits.hpp"

#include <BRepTools.hxx>
#include <BRep_Tool.hxx>
#include <BndLib_Add2dCurve.hxx>
#include <Bnd_Box2d.hxx>
#include <Geom2dAdaptor_Curve.hxx>
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

}  // namespace

FaceLineIntersector::FaceLineIntersector(const TopoDS_Face& face, double tolerance)
    : face_(face), full_intersector_(face, tolerance, true, true) {
  surface_ = new BRepAdaptor_Surface(face, true);
  analytic_ = is_analytic(surface_->GetType());
  if (!analytic_) return;
  BRepTools::UVBounds(face, u0_, u1_, v0_, v1_);
  if (!(u1_ > u0_ && v1_ > v0_)) {
    analytic_ = false;
    return;
  }
  const double uv_tol = uv_tolerance(face, *surface_, tolerance);
  classifier_ = std::make_unique<BRepTopAdaptor_FClass2d>(face, uv_tol);
  nu_ = nv_ = kBins;
  bins_.assign(static_cast<size_t>(nu_) * static_cast<size_t>(nv_), Bin::kUnknown);
  mark_trimming_curves();
  if (analytic_) label_regions();
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
      analytic_ = false;  // no trimming curve to box: every line takes the full path
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
        analytic_ = false;
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
    hits.push_back({full_intersector_.WParameter(i), transition == IntCurveSurface_In    ? 1
                                                     : transition == IntCurveSurface_Out ? -1
                                                                                         : 0});
  }
}

void FaceLineIntersector::perform(const gp_Lin& line, double w0, double w1,
                                  std::vector<FaceHit>& hits) {
  if (!analytic_) return perform_full(line, w0, w1, hits);
  // The surface intersection exactly as IntCurvesFace_Intersector does it for these surfaces.
  IntCurveSurface_HInter intersection;
  const Handle(GeomAdaptor_Curve) curve = new GeomAdaptor_Curve(new Geom_Line(line));
  intersection.Perform(curve, surface_);
  if (!intersection.IsDone()) return perform_full(line, w0, w1, hits);
  const size_t start = hits.size();
  const bool reversed = face_.Orientation() == TopAbs_REVERSED;
  for (int i = 1; i <= intersection.NbPoints(); ++i) {
    const IntCurveSurface_IntersectionPoint& point = intersection.Point(i);
    if (point.W() < w0 || point.W() > w1) continue;
    const Bin state = bin_state(point.U(), point.V());
    if (state == Bin::kBoundary) {
      hits.resize(start);
      return perform_full(line, w0, w1, hits);
    }
    if (state == Bin::kOut) continue;
    int net = point.Transition() == IntCurveSurface_In    ? 1
              : point.Transition() == IntCurveSurface_Out ? -1
                                                          : 0;
    if (reversed) net = -net;
    hits.push_back({point.W(), net});
  }
  ++fast_;
}

}  // namespace isospring::geometry::detail
