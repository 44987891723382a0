// Quadrature on the exact trimmed faces of a solid (immersed_cad_faces.hpp).
#include "immersed_cad_faces.hpp"

#include <BRepAdaptor_Surface.hxx>
#include <BRepTools.hxx>
#include <BRep_Tool.hxx>
#include <Geom2dAdaptor_Curve.hxx>
#include <Geom2dHatch_Hatcher.hxx>
#include <Geom2dHatch_Intersector.hxx>
#include <Geom2d_Curve.hxx>
#include <Geom2d_Line.hxx>
#include <HatchGen_Domain.hxx>
#include <Standard_Failure.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "isospring/nurbs/quadrature.hpp"

namespace isospring::geometry::detail {

namespace {

struct TrimCurve {
  Handle(Geom2d_Curve) curve;
  double first = 0.0, last = 0.0;
  TopAbs_Orientation orientation = TopAbs_FORWARD;
};

// u of the curve at its ends, at its non-C2 points and where du/dt changes sign (there an
// iso-line u = const touches the trimming curve: the v-limits have a square-root behaviour in u).
void curve_breaks(const TrimCurve& c, std::vector<double>& breaks) {
  Geom2dAdaptor_Curve adaptor(c.curve, c.first, c.last);
  const int intervals = adaptor.NbIntervals(GeomAbs_C2);
  TColStd_Array1OfReal ends(1, intervals + 1);
  adaptor.Intervals(ends, GeomAbs_C2);
  for (int i = 1; i <= intervals + 1; ++i) breaks.push_back(adaptor.Value(ends(i)).X());
  const auto du = [&](double t) {
    gp_Pnt2d p;
    gp_Vec2d d;
    adaptor.D1(t, p, d);
    return d.X();
  };
  constexpr int kSamples = 64;
  double t0 = c.first, d0 = du(t0);
  for (int k = 1; k <= kSamples; ++k) {
    const double t1 = c.first + (c.last - c.first) * k / kSamples, d1 = du(t1);
    if (d0 * d1 < 0.0) {  // bisection to the extremum of u
      double a = t0, b = t1, da = d0;
      for (int it = 0; it < 60 && b - a > 1e-15 * (c.last - c.first); ++it) {
        const double m = 0.5 * (a + b), dm = du(m);
        if (da * dm <= 0.0) {
          b = m;
        } else {
          a = m;
          da = dm;
        }
      }
      breaks.push_back(adaptor.Value(0.5 * (a + b)).X());
    }
    t0 = t1;
    d0 = d1;
  }
}

std::vector<double> surface_breaks(const BRepAdaptor_Surface& surface, bool u) {
  const int n = u ? surface.NbUIntervals(GeomAbs_C2) : surface.NbVIntervals(GeomAbs_C2);
  TColStd_Array1OfReal ends(1, n + 1);
  if (u)
    surface.UIntervals(ends, GeomAbs_C2);
  else
    surface.VIntervals(ends, GeomAbs_C2);
  return std::vector<double>(ends.begin(), ends.end());
}

// The hatcher's confusion distance in (u, v): iso-lines and trimming curves closer than this meet.
// It bounds how exactly an iso-line's ends are placed, so it is also relative to the face's
// parameter range (hatch_confusion): on a planar face, whose (u, v) are metres, 1e-8 m is 1e-5 of
// a millimetre part's side, and Analysis Situs' 1 mm wavy cube came out with two side faces 1.05e-5
// too large.
constexpr double kHatchConfusion = 1e-8;
constexpr double kRelativeHatchConfusion = 1e-7;

double hatch_confusion(double u_range, double v_range) {
  return std::min(kHatchConfusion, kRelativeHatchConfusion * std::max(u_range, v_range));
}

// Sorted break points in [lo, hi], both ends included, without near-duplicates. Breaks closer than
// the hatcher's confusion distance are one: a trimming curve fitted by a polynomial (a circle's
// pcurve) overshoots the u of its end vertex by a few 1e-9 (the CAx-IF GD&T block: 5.7e-9), and
// every iso-line in that sliver grazes the curve within the hatcher's tolerance, so the hatcher
// fails on it; the sliver's area is below 1e-8 of the face's u range times its v-extent there.
std::vector<double> cleaned(std::vector<double> breaks, double lo, double hi, double confusion) {
  breaks.push_back(lo);
  breaks.push_back(hi);
  std::vector<double> kept;
  std::sort(breaks.begin(), breaks.end());
  for (double b : breaks) {
    if (b < lo || b > hi) continue;
    if (!kept.empty() && b - kept.back() <= std::max(1e-12 * (hi - lo), confusion)) continue;
    kept.push_back(b);
  }
  if (kept.back() < hi) kept.back() = hi;
  return kept;
}

// A face's parameter bounds (BRepTools::UVBounds).
struct UvBox {
  double u0 = 0, u1 = 0, v0 = 0, v1 = 0;
};

UvBox uv_box(const TopoDS_Face& face) {
  UvBox box;
  BRepTools::UVBounds(face, box.u0, box.u1, box.v0, box.v1);
  return box;
}

class FaceIntegrator {
 public:
  FaceIntegrator(const TopoDS_Face& face, int index, int order)
      : face_(face),
        index_(index),
        rule_(nurbs::gauss_legendre(order)),
        surface_(face, true),
        box_(uv_box(face)),
        confusion_(hatch_confusion(box_.u1 - box_.u0, box_.v1 - box_.v0)),
        hatcher_(Geom2dHatch_Intersector(1e-10, 1e-10), confusion_, confusion_, true, false) {
    std::vector<double> ubreaks = surface_breaks(surface_, true);
    const TopoDS_Face forward = TopoDS::Face(face.Oriented(TopAbs_FORWARD));
    for (TopExp_Explorer e(forward, TopAbs_EDGE); e.More(); e.Next()) {
      const TopoDS_Edge& edge = TopoDS::Edge(e.Current());
      TrimCurve c;
      c.curve = BRep_Tool::CurveOnSurface(edge, forward, c.first, c.last);
      if (c.curve.IsNull()) continue;
      c.orientation = edge.Orientation();
      curve_breaks(c, ubreaks);
      hatcher_.AddElement(Geom2dAdaptor_Curve(c.curve, c.first, c.last), c.orientation);
    }
    ubreaks_ = cleaned(ubreaks, box_.u0, box_.u1, confusion_);
    vbreaks_ = surface_breaks(surface_, false);
  }

  // Points with every interval between u break points cut into `pieces` x its share of the
  // face's u range, and v pieces no longer than 1 / `pieces` of the v range.
  std::vector<BoundaryPoint> points(int pieces) {
    std::vector<BoundaryPoint> out;
    for (size_t b = 0; b + 1 < ubreaks_.size(); ++b) {
      const double a = ubreaks_[b], c = ubreaks_[b + 1];
      const int n =
          std::max(1, static_cast<int>(std::ceil(pieces * (c - a) / (box_.u1 - box_.u0))));
      // Where an iso-line touches a trimming curve (a u-extremum, e.g. the ends of a disc) the
      // v-range behaves like sqrt(u - a): the substitution u = a + (c - a) s(t) with
      // s = 3t^2 - 2t^3 (s' = 0 at both ends) makes it smooth in t, so Gauss converges
      // exponentially again; smooth integrands stay smooth.
      for (int k = 0; k < n; ++k)
        for (size_t g = 0; g < rule_.points.size(); ++g) {
          const double t = (k + 0.5 * (1.0 + rule_.points[g])) / n;
          const double s = t * t * (3.0 - 2.0 * t), ds = 6.0 * t * (1.0 - t);
          add_iso_line(a + (c - a) * s, (c - a) * ds * 0.5 * rule_.weights[g] / n, pieces, out);
        }
    }
    return out;
  }

 private:
  void add_iso_line(double u, double wu, int pieces, std::vector<BoundaryPoint>& out) {
    const int id = hatcher_.AddHatching(
        Geom2dAdaptor_Curve(new Geom2d_Line(gp_Pnt2d(u, 0.0), gp_Dir2d(0.0, 1.0))));
    hatcher_.Trim(id);
    hatcher_.ComputeDomains(id);
    if (!hatcher_.IsDone(id)) {
      hatcher_.RemHatching(id);
      throw std::runtime_error("OpenCascade's hatcher failed on an iso-line of the face");
    }
    for (int d = 1; d <= hatcher_.NbDomains(id); ++d) {
      const HatchGen_Domain& domain = hatcher_.Domain(id, d);
      const double a = domain.HasFirstPoint() ? domain.FirstPoint().Parameter() : box_.v0;
      const double b = domain.HasSecondPoint() ? domain.SecondPoint().Parameter() : box_.v1;
      add_v_interval(u, wu, std::max(a, box_.v0), std::min(b, box_.v1), pieces, out);
    }
    hatcher_.RemHatching(id);
  }

  void add_v_interval(double u, double wu, double a, double b, int pieces,
                      std::vector<BoundaryPoint>& out) const {
    if (!(b > a)) return;
    std::vector<double> breaks = vbreaks_;
    const std::vector<double> v = cleaned(breaks, a, b, confusion_);
    const bool reversed = face_.Orientation() == TopAbs_REVERSED;
    for (size_t s = 0; s + 1 < v.size(); ++s) {
      const int n = std::max(
          1, static_cast<int>(std::ceil(pieces * (v[s + 1] - v[s]) / (box_.v1 - box_.v0))));
      const double h = (v[s + 1] - v[s]) / n;
      for (int k = 0; k < n; ++k)
        for (size_t g = 0; g < rule_.points.size(); ++g) {
          const double vv = v[s] + h * (k + 0.5 * (1.0 + rule_.points[g]));
          gp_Pnt p;
          gp_Vec du, dv;
          surface_.D1(u, vv, p, du, dv);
          gp_Vec normal = du.Crossed(dv);
          const double jacobian = normal.Magnitude();
          if (!(jacobian > 0.0)) continue;  // a pole: no area
          normal /= jacobian;
          if (reversed) normal.Reverse();
          BoundaryPoint point;
          point.point = {p.X(), p.Y(), p.Z()};
          point.normal = {normal.X(), normal.Y(), normal.Z()};
          point.weight = wu * 0.5 * h * rule_.weights[g] * jacobian;
          point.face = index_;
          out.push_back(point);
        }
    }
  }

  TopoDS_Face face_;
  int index_;
  nurbs::GaussRule rule_;
  BRepAdaptor_Surface surface_;
  UvBox box_;
  double confusion_;
  Geom2dHatch_Hatcher hatcher_;
  std::vector<double> ubreaks_, vbreaks_;
};

// A face's rule is accepted when doubling its pieces changes its area and first moments by less
// than this (relative); at most kDoublings rules are compared (each has four times the points of
// the one before: trimming curves that are splines of many knots settle slowly).
constexpr double kSettled = 1e-9;
constexpr int kDoublings = 3;

// Area and first moments of a face's points, for the convergence test.
Eigen::Vector4d moments(const std::vector<BoundaryPoint>& points) {
  Eigen::Vector4d m = Eigen::Vector4d::Zero();
  for (const BoundaryPoint& p : points)
    m += p.weight * Eigen::Vector4d(1.0, p.point.x(), p.point.y(), p.point.z());
  return m;
}

}  // namespace

double face_surface_length(const TopoDS_Face& face) {
  BRepAdaptor_Surface surface(face, true);
  double u0, u1, v0, v1;
  BRepTools::UVBounds(face, u0, u1, v0, v1);
  double length = 0.0;
  for (int k = 0; k < 8; ++k) {
    const double s = k / 8.0, t = (k + 1) / 8.0;
    length += surface.Value(u0 + s * (u1 - u0), v0 + s * (v1 - v0))
                  .Distance(surface.Value(u0 + t * (u1 - u0), v0 + t * (v1 - v0)));
  }
  return length;
}

std::vector<BoundaryPoint> face_quadrature(const CadSolid::Shape& shape, int order,
                                           double piece_length,
                                           std::vector<std::string>& warnings) {
  std::vector<BoundaryPoint> all;
  for (size_t f = 0; f < shape.faces.size(); ++f) {
    const TopoDS_Face& face = shape.faces[f];
    const int index = shape.face_index[f];
    try {
      FaceIntegrator integrator(face, index, order);
      // Pieces from the face's size on the surface (its UV box's diagonal image), so that a
      // piece spans about one background cell or less.
      const double length = face_surface_length(face);
      int pieces = std::max(1, static_cast<int>(std::ceil(length / piece_length)));
      std::vector<BoundaryPoint> coarse = integrator.points(pieces);
      std::vector<BoundaryPoint> fine = integrator.points(2 * pieces);
      // First moments relative to area x (distance from the origin + the face's extent).
      const auto change = [](const std::vector<BoundaryPoint>& x,
                             const std::vector<BoundaryPoint>& y) {
        const Eigen::Vector4d a = moments(x), b = moments(y);
        const double area = std::max(std::abs(b[0]), 1e-300);
        const double arm = b.tail<3>().norm() / area + std::sqrt(area);
        return std::max(std::abs(a[0] - b[0]) / area,
                        (a.tail<3>() - b.tail<3>()).norm() / (area * arm));
      };
      double last = change(coarse, fine);
      for (int doublings = 1; doublings < kDoublings && last > kSettled; ++doublings) {
        pieces *= 2;
        coarse = std::move(fine);
        fine = integrator.points(2 * pieces);
        last = change(coarse, fine);
      }
      // A change below 1e-7 is still far below what an analysis sees.
      if (last > 1e-7) {
        std::ostringstream out;
        out.precision(2);
        out << "face " << index << ": its quadrature changed by " << last
            << " (relative) at the last of " << kDoublings - 1 << " doublings";
        warnings.push_back(out.str());
      }
      all.insert(all.end(), fine.begin(), fine.end());
    } catch (const Standard_Failure& e) {
      throw std::runtime_error("face " + std::to_string(index) +
                               ": OpenCascade failed integrating it (" + e.GetMessageString() +
                               ")");
    }
  }
  return all;
}

}  // namespace isospring::geometry::detail
