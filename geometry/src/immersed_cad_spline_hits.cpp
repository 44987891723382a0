// A line against a B-spline surface by Bezier subdivision and Newton's method
// (immersed_cad_spline_hits.hpp).
#include "immersed_cad_spline_hits.hpp"

#include <GeomConvert.hxx>
#include <GeomConvert_BSplineSurfaceToBezierSurface.hxx>
#include <Geom_BSplineSurface.hxx>
#include <Geom_BezierSurface.hxx>
#include <Standard_Failure.hxx>
#include <TColGeom_Array2OfBezierSurface.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColStd_Array2OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace isospring::geometry::detail {

namespace {

// Halvings of a Bezier patch before a piece that still holds 0 in its net's box counts as
// uncertain (a patch edge then shrinks by 2^-12; only lines grazing the surface get there).
constexpr int kMaxDepth = 12;
// The injectivity bound: every J0^-1 J(x) within this (Frobenius) distance of the identity.
constexpr double kContraction = 0.5;
// A hit whose line meets the surface at |cos| below this is a near-tangency: left to OpenCascade.
constexpr double kGrazing = 1e-6;
constexpr int kNewtonSteps = 30;

using Net = std::vector<Eigen::Vector2d>;
// Halvings of each patch in u and v for the boxes of may_meet().
constexpr int kBoxDepth = 3;

// De Casteljau halves of a net (nu x nv, index i + nu j) in u (along i) or in v.
template <typename Point>
void split(const std::vector<Point>& net, int nu, int nv, bool in_u, std::vector<Point>& low,
           std::vector<Point>& high) {
  low = net;
  high = net;
  const int n = in_u ? nu : nv, lines = in_u ? nv : nu;
  std::vector<Point> work(static_cast<size_t>(n));
  for (int l = 0; l < lines; ++l) {
    const auto at = [&](int k) { return static_cast<size_t>(in_u ? k + nu * l : l + nu * k); };
    for (int k = 0; k < n; ++k) work[static_cast<size_t>(k)] = net[at(k)];
    for (int r = 0; r < n; ++r) {
      low[at(r)] = work[0];
      high[at(n - 1 - r)] = work[static_cast<size_t>(n - 1 - r)];
      for (int k = 0; k + 1 < n - r; ++k)
        work[static_cast<size_t>(k)] =
            0.5 * (work[static_cast<size_t>(k)] + work[static_cast<size_t>(k + 1)]);
    }
  }
}

// Does the net certify that its map is injective on the piece (see the header)?
bool injective(const Net& net, int nu, int nv) {
  Eigen::Vector2d mean_u = Eigen::Vector2d::Zero(), mean_v = Eigen::Vector2d::Zero();
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i + 1 < nu; ++i)
      mean_u += net[static_cast<size_t>(i + 1 + nu * j)] - net[static_cast<size_t>(i + nu * j)];
  for (int j = 0; j + 1 < nv; ++j)
    for (int i = 0; i < nu; ++i)
      mean_v += net[static_cast<size_t>(i + nu * (j + 1))] - net[static_cast<size_t>(i + nu * j)];
  mean_u /= static_cast<double>((nu - 1) * nv);
  mean_v /= static_cast<double>(nu * (nv - 1));
  Eigen::Matrix2d j0;
  j0 << mean_u, mean_v;
  const double det = j0.determinant();
  if (!(std::abs(det) > 1e-14 * j0.squaredNorm())) return false;
  const Eigen::Matrix2d inverse = j0.inverse();
  double worst_u = 0.0, worst_v = 0.0;
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i + 1 < nu; ++i) {
      const Eigen::Vector2d d =
          net[static_cast<size_t>(i + 1 + nu * j)] - net[static_cast<size_t>(i + nu * j)];
      worst_u = std::max(worst_u, (inverse * d - Eigen::Vector2d(1.0, 0.0)).squaredNorm());
    }
  for (int j = 0; j + 1 < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const Eigen::Vector2d d =
          net[static_cast<size_t>(i + nu * (j + 1))] - net[static_cast<size_t>(i + nu * j)];
      worst_v = std::max(worst_v, (inverse * d - Eigen::Vector2d(0.0, 1.0)).squaredNorm());
    }
  return worst_u + worst_v < kContraction * kContraction;
}

// The Bezier patches of a B-spline surface over the box (empty when OpenCascade cannot cut it).
Handle(Geom_BSplineSurface) spline_of(const BRepAdaptor_Surface& surface) {
  if (surface.GetType() == GeomAbs_BSplineSurface) return surface.BSpline();
  if (surface.GetType() == GeomAbs_BezierSurface)
    return GeomConvert::SurfaceToBSplineSurface(surface.Bezier());
  return nullptr;
}

}  // namespace

SplineLineHits::SplineLineHits(const BRepAdaptor_Surface& surface, double u0, double u1, double v0,
                               double v1)
    : surface_(surface) {
  try {
    const Handle(Geom_BSplineSurface) spline = spline_of(surface);
    if (spline.IsNull()) return;
    double su0, su1, sv0, sv1;
    spline->Bounds(su0, su1, sv0, sv1);
    // A box reaching past a periodic surface's period would need its other turns: not done.
    const double slack = 1e-9 * std::max(su1 - su0, sv1 - sv0);
    if (u0 < su0 - slack || u1 > su1 + slack || v0 < sv0 - slack || v1 > sv1 + slack) return;
    u0 = std::max(u0, su0);
    u1 = std::min(u1, su1);
    v0 = std::max(v0, sv0);
    v1 = std::min(v1, sv1);
    if (!(u1 > u0 && v1 > v0)) return;
    GeomConvert_BSplineSurfaceToBezierSurface convert(spline, u0, u1, v0, v1, 1e-12);
    TColGeom_Array2OfBezierSurface beziers(1, convert.NbUPatches(), 1, convert.NbVPatches());
    convert.Patches(beziers);
    TColStd_Array1OfReal uknots(1, convert.NbUPatches() + 1), vknots(1, convert.NbVPatches() + 1);
    convert.UKnots(uknots);
    convert.VKnots(vknots);
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
    for (int a = 1; a <= convert.NbUPatches(); ++a)
      for (int b = 1; b <= convert.NbVPatches(); ++b) {
        const Handle(Geom_BezierSurface)& bezier = beziers(a, b);
        Patch patch;
        patch.nu = bezier->NbUPoles();
        patch.nv = bezier->NbVPoles();
        patch.ua = uknots(a);
        patch.ub = uknots(a + 1);
        patch.va = vknots(b);
        patch.vb = vknots(b + 1);
        TColgp_Array2OfPnt poles(1, patch.nu, 1, patch.nv);
        bezier->Poles(poles);
        TColStd_Array2OfReal weights(1, patch.nu, 1, patch.nv);
        bezier->Weights(weights);
        patch.lo = Eigen::Vector3d::Constant(1e300);
        patch.hi = -patch.lo;
        for (int j = 1; j <= patch.nv; ++j)
          for (int i = 1; i <= patch.nu; ++i) {
            const gp_Pnt& p = poles(i, j);
            const double w = weights(i, j);
            if (!(w > 0.0)) {  // no convex hull property: not this path
              patches_.clear();
              return;
            }
            const Eigen::Vector3d x(p.X(), p.Y(), p.Z());
            patch.poles.emplace_back(w * x.x(), w * x.y(), w * x.z(), w);
            patch.lo = patch.lo.cwiseMin(x);
            patch.hi = patch.hi.cwiseMax(x);
          }
        lo = lo.cwiseMin(patch.lo);
        hi = hi.cwiseMax(patch.hi);
        add_piece_boxes(patch.poles, patch.nu, patch.nv, 0);
        patches_.push_back(std::move(patch));
      }
    scale_ = std::max((hi - lo).norm(), 1e-300);
  } catch (const Standard_Failure&) {
    patches_.clear();
  }
}

void SplineLineHits::add_piece_boxes(const std::vector<Eigen::Vector4d>& net, int nu, int nv,
                                     int depth) {
  if (depth == kBoxDepth) {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
    for (const Eigen::Vector4d& x : net) {
      lo = lo.cwiseMin(x.head<3>() / x[3]);
      hi = hi.cwiseMax(x.head<3>() / x[3]);
    }
    piece_lo_.push_back(lo);
    piece_hi_.push_back(hi);
    return;
  }
  std::vector<Eigen::Vector4d> low, high;
  split(net, nu, nv, true, low, high);
  for (const auto* half : {&low, &high}) {
    std::vector<Eigen::Vector4d> a, b;
    split(*half, nu, nv, false, a, b);
    add_piece_boxes(a, nu, nv, depth + 1);
    add_piece_boxes(b, nu, nv, depth + 1);
  }
}

bool SplineLineHits::may_meet(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) const {
  for (size_t k = 0; k < piece_lo_.size(); ++k)
    if ((piece_lo_[k].array() <= hi.array()).all() && (piece_hi_[k].array() >= lo.array()).all())
      return true;
  return false;
}

bool SplineLineHits::intersect(const gp_Lin& line, double w0, double w1,
                               std::vector<SurfaceHit>& hits) const {
  const Eigen::Vector3d p(line.Location().X(), line.Location().Y(), line.Location().Z());
  const Eigen::Vector3d d(line.Direction().X(), line.Direction().Y(), line.Direction().Z());
  // e1, e2: an orthonormal pair normal to d.
  int smallest = 0;
  d.cwiseAbs().minCoeff(&smallest);
  const Eigen::Vector3d e1 = d.cross(Eigen::Vector3d::Unit(smallest)).normalized();
  const Eigen::Vector3d e2 = d.cross(e1);
  const double margin = 1e-9 * scale_;
  std::vector<SurfaceHit> found;
  for (const Patch& patch : patches_) {
    // The line against the patch's box (slabs, enlarged by the margin).
    double ta = -1e300, tb = 1e300;
    bool misses = false;
    for (int k = 0; k < 3 && !misses; ++k) {
      const double lo = patch.lo[k] - margin, hi = patch.hi[k] + margin;
      if (std::abs(d[k]) < 1e-300) {
        misses = p[k] < lo || p[k] > hi;
      } else {
        double a = (lo - p[k]) / d[k], b = (hi - p[k]) / d[k];
        if (a > b) std::swap(a, b);
        ta = std::max(ta, a);
        tb = std::min(tb, b);
        misses = ta > tb;
      }
    }
    if (misses || tb < w0 - margin || ta > w1 + margin) continue;
    Net net(patch.poles.size());
    for (size_t k = 0; k < net.size(); ++k) {
      const Eigen::Vector3d x = patch.poles[k].head<3>() - patch.poles[k][3] * p;
      net[k] = Eigen::Vector2d(e1.dot(x), e2.dot(x));
    }
    if (!search(patch, net, {0.0, 1.0, 0.0, 1.0}, 0, line, found)) return false;
  }
  // A hit on the common side of two pieces (or patches) is found by both.
  std::sort(found.begin(), found.end(),
            [](const SurfaceHit& a, const SurfaceHit& b) { return a.w < b.w; });
  const double same = 1e-9 * scale_;
  for (size_t k = 0; k < found.size(); ++k) {
    const SurfaceHit& hit = found[k];
    if (k > 0 && hit.w - found[k - 1].w <= same) {
      if ((hit.cosine > 0.0) != (found[k - 1].cosine > 0.0)) return false;  // a fold: unclear
      continue;
    }
    if (hit.w < w0 || hit.w > w1) continue;
    hits.push_back(hit);
  }
  return true;
}

bool SplineLineHits::search(const Patch& patch, const Net& net, const Piece& piece, int depth,
                            const gp_Lin& line, std::vector<SurfaceHit>& found) const {
  Eigen::Vector2d lo = net[0], hi = net[0];
  double size = 0.0;
  for (const Eigen::Vector2d& g : net) {
    lo = lo.cwiseMin(g);
    hi = hi.cwiseMax(g);
    size = std::max(size, g.cwiseAbs().maxCoeff());
  }
  const double slack = 1e-12 * size;
  if ((lo.array() > slack).any() || (hi.array() < -slack).any()) return true;  // no zero here
  if (injective(net, patch.nu, patch.nv)) return newton(patch, piece, line, found);
  if (depth >= kMaxDepth) return false;
  Net low, high, quarter[4];
  split(net, patch.nu, patch.nv, true, low, high);
  split(low, patch.nu, patch.nv, false, quarter[0], quarter[1]);
  split(high, patch.nu, patch.nv, false, quarter[2], quarter[3]);
  const double sm = 0.5 * (piece.s0 + piece.s1), tm = 0.5 * (piece.t0 + piece.t1);
  const Piece pieces[4] = {{piece.s0, sm, piece.t0, tm},
                           {piece.s0, sm, tm, piece.t1},
                           {sm, piece.s1, piece.t0, tm},
                           {sm, piece.s1, tm, piece.t1}};
  for (int c = 0; c < 4; ++c)
    if (!search(patch, quarter[c], pieces[c], depth + 1, line, found)) return false;
  return true;
}

// Newton's method on S(u, v) = p + w d from the piece's centre. The piece holds at most one zero;
// one found inside it (to a hair) is a hit, one outside belongs to another piece.
bool SplineLineHits::newton(const Patch& patch, const Piece& piece, const gp_Lin& line,
                            std::vector<SurfaceHit>& found) const {
  const Eigen::Vector3d p(line.Location().X(), line.Location().Y(), line.Location().Z());
  const Eigen::Vector3d d(line.Direction().X(), line.Direction().Y(), line.Direction().Z());
  const double du = patch.ub - patch.ua, dv = patch.vb - patch.va;
  double u = patch.ua + du * 0.5 * (piece.s0 + piece.s1);
  double v = patch.va + dv * 0.5 * (piece.t0 + piece.t1);
  gp_Pnt point;
  gp_Vec su, sv;
  surface_.D1(u, v, point, su, sv);
  double w = d.dot(Eigen::Vector3d(point.X(), point.Y(), point.Z()) - p);
  bool converged = false;
  for (int step = 0; step < kNewtonSteps && !converged; ++step) {
    const Eigen::Vector3d x(point.X(), point.Y(), point.Z());
    const Eigen::Vector3d f = x - p - w * d;
    Eigen::Matrix3d j;
    j << Eigen::Vector3d(su.X(), su.Y(), su.Z()), Eigen::Vector3d(sv.X(), sv.Y(), sv.Z()), -d;
    const Eigen::Vector3d delta = j.partialPivLu().solve(-f);
    if (!delta.allFinite()) return false;
    u += delta[0];
    v += delta[1];
    w += delta[2];
    converged = std::abs(delta[0]) <= 1e-14 * du && std::abs(delta[1]) <= 1e-14 * dv &&
                std::abs(delta[2]) <= 1e-14 * scale_;
    // A step far outside the patch: the zero is not in this piece (or Newton is lost).
    if (u < patch.ua - du || u > patch.ub + du || v < patch.va - dv || v > patch.vb + dv)
      return true;
    surface_.D1(u, v, point, su, sv);
    if (!converged && step == kNewtonSteps - 1) {
      // Converged to round-off even if the steps did not shrink below the bound.
      const Eigen::Vector3d r = Eigen::Vector3d(point.X(), point.Y(), point.Z()) - p - w * d;
      converged = r.norm() <= 1e-13 * scale_;
    }
  }
  if (!converged) return false;
  const double hair = 1e-9;
  const double s = (u - patch.ua) / du, t = (v - patch.va) / dv;
  if (s < piece.s0 - hair || s > piece.s1 + hair || t < piece.t0 - hair || t > piece.t1 + hair)
    return true;
  const gp_Vec normal = su.Crossed(sv);
  const double length = normal.Magnitude();
  if (!(length > 0.0)) return false;
  const double cosine = (normal.X() * d.x() + normal.Y() * d.y() + normal.Z() * d.z()) / length;
  if (std::abs(cosine) < kGrazing) return false;
  found.push_back({u, v, w, cosine});
  return true;
}

}  // namespace isospring::geometry::detail
