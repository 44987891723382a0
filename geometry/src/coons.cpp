// Exact NURBS Coons patches: compatible boundary curves and the Greville-abscissae control net.
#include "isospring/geometry/coons.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "isospring/nurbs/refine.hpp"

namespace isospring::geometry {

using nurbs::KnotVector;
using nurbs::Patch;

namespace {

// The curve over [0, 1] (an affine change of parameter leaves the geometry unchanged).
Patch to_unit_interval(const Patch& curve) {
  const KnotVector& kv = curve.knots(0);
  const double a = kv.first(), b = kv.last();
  std::vector<double> t;
  for (double x : kv.values()) t.push_back((x - a) / (b - a));
  return Patch({KnotVector(kv.degree(), t, "boundary curve knots")}, curve.control_points(),
               curve.weights());
}

// A knot value of `kv` within `tol` of x (NAN when there is none).
double nearby_knot(const KnotVector& kv, double x, double tol) {
  for (double k : kv.unique())
    if (std::abs(k - x) <= tol) return k;
  return NAN;
}

}  // namespace

std::vector<double> greville_abscissae(const KnotVector& knots) {
  const int p = knots.degree();
  std::vector<double> g(static_cast<size_t>(knots.num_basis()), 0.0);
  for (int i = 0; i < knots.num_basis(); ++i) {
    double sum = 0.0;
    for (int k = 1; k <= p; ++k) sum += knots[i + k];
    g[static_cast<size_t>(i)] = p > 0 ? sum / p : knots[i];
  }
  return g;
}

std::vector<Patch> make_compatible(const std::vector<Patch>& curves, double knot_tolerance) {
  std::vector<Patch> result;
  int degree = 0;
  for (const Patch& c : curves) {
    if (c.param_dim() != 1) throw std::invalid_argument("make_compatible: curves only");
    result.push_back(to_unit_interval(c));
    degree = std::max(degree, c.degree(0));
  }
  for (Patch& c : result) c = nurbs::elevate_degree(c, 0, degree - c.degree(0));
  // Interior knots of all curves, clustered within the tolerance; each cluster needs the largest
  // multiplicity any curve has there.
  std::vector<std::pair<double, int>> merged;
  std::vector<std::pair<double, int>> all;
  for (const Patch& c : result) {
    const auto u = c.knots(0).unique();
    const auto m = c.knots(0).multiplicities();
    for (size_t i = 1; i + 1 < u.size(); ++i) all.emplace_back(u[i], m[i]);
  }
  std::sort(all.begin(), all.end());
  for (const auto& [x, m] : all) {
    if (!merged.empty() && x - merged.back().first <= knot_tolerance)
      merged.back().second = std::max(merged.back().second, m);
    else
      merged.emplace_back(x, m);
  }
  for (Patch& c : result) {
    std::vector<double> insert;
    for (const auto& [x, m] : merged) {
      const double own = nearby_knot(c.knots(0), x, knot_tolerance);
      const int have = std::isnan(own) ? 0 : c.knots(0).multiplicity(own);
      for (int k = have; k < m; ++k) insert.push_back(std::isnan(own) ? x : own);
    }
    c = nurbs::refine_knots(c, 0, insert);
  }
  // Same knot count now; values differ by at most the tolerance: use the first curve's.
  const KnotVector common = result.front().knots(0);  // a copy: the curves are replaced
  for (Patch& c : result) {
    for (int i = 0; i < common.size(); ++i)
      if (std::abs(c.knots(0)[i] - common[i]) > knot_tolerance)
        throw std::logic_error("make_compatible: knot vectors differ after refinement");
    c = Patch({common}, c.control_points(), c.weights());
  }
  return result;
}

Patch coons_patch(const Patch& bottom, const Patch& right, const Patch& top, const Patch& left,
                  double corner_tolerance) {
  for (const Patch* c : {&bottom, &right, &top, &left})
    if (c->param_dim() != 1) throw std::invalid_argument("coons_patch: boundary curves only");
  const std::vector<Patch> u_pair = make_compatible({bottom, top});
  const std::vector<Patch> v_pair = make_compatible({left, right});
  using H = Eigen::Vector4d;  // homogeneous point (w x, w)
  auto homogeneous = [](const Patch& c) {
    std::vector<H> h;
    for (int a = 0; a < c.num_points(); ++a) {
      const double w = c.weight(a);
      h.emplace_back(w * c.control_point(a).x(), w * c.control_point(a).y(),
                     w * c.control_point(a).z(), w);
    }
    return h;
  };
  std::vector<H> B = homogeneous(u_pair[0]), T = homogeneous(u_pair[1]), L = homogeneous(v_pair[0]),
                 R = homogeneous(v_pair[1]);
  const size_t nu = B.size(), nv = L.size();
  // Corner weights must agree: scale L, R, T (a constant factor leaves a rational curve as it is).
  const double sL = B[0].w() / L[0].w(), sR = B[nu - 1].w() / R[0].w();
  const double sT = sL * L[nv - 1].w() / T[0].w();
  if (std::abs(sT * T[nu - 1].w() - sR * R[nv - 1].w()) > 1e-12 * std::abs(sR * R[nv - 1].w()))
    throw std::invalid_argument(
        "coons_patch: the rational boundary curves' end weights cannot be matched at the corners");
  for (H& h : L) h *= sL;
  for (H& h : R) h *= sR;
  for (H& h : T) h *= sT;
  // Merge each corner pair (same weight now) at its midpoint.
  auto merge = [&](H& a, H& b, const char* name) {
    const double distance = (a.head<3>() / a.w() - b.head<3>() / b.w()).norm();
    if (distance > corner_tolerance) {
      std::ostringstream msg;
      msg << "coons_patch: the boundary curves do not meet at corner " << name << " (gap "
          << distance << ")";
      throw std::invalid_argument(msg.str());
    }
    a = b = 0.5 * (a + b);
  };
  merge(B[0], L[0], "(0,0)");
  merge(B[nu - 1], R[0], "(1,0)");
  merge(T[0], L[nv - 1], "(0,1)");
  merge(T[nu - 1], R[nv - 1], "(1,1)");
  const H c00 = B[0], c10 = B[nu - 1], c01 = T[0], c11 = T[nu - 1];
  const std::vector<double> gu = greville_abscissae(u_pair[0].knots(0));
  const std::vector<double> gv = greville_abscissae(v_pair[0].knots(0));
  const bool rational =
      bottom.is_rational() || right.is_rational() || top.is_rational() || left.is_rational();
  std::vector<Eigen::Vector3d> points;
  std::vector<double> weights;
  for (size_t j = 0; j < nv; ++j)
    for (size_t i = 0; i < nu; ++i) {
      const double u = gu[i], v = gv[j];
      const H p = (1 - v) * B[i] + v * T[i] + (1 - u) * L[j] + u * R[j] -
                  ((1 - u) * (1 - v) * c00 + u * (1 - v) * c10 + (1 - u) * v * c01 + u * v * c11);
      if (!(p.w() > 0.0))
        throw std::invalid_argument("coons_patch: a blended weight is not positive");
      points.emplace_back(p.head<3>() / p.w());
      weights.push_back(p.w());
    }
  if (!rational) weights.clear();  // every weight is 1 + 1 - 1: keep the patch polynomial
  return Patch({u_pair[0].knots(0), v_pair[0].knots(0)}, points, weights);
}

}  // namespace isospring::geometry

namespace isospring::geometry {

namespace {

using H = Eigen::Vector4d;  // homogeneous control point (w x, w)

// A face's control net in homogeneous coordinates, indexed (first direction, second direction).
struct Net {
  int n0 = 0;
  std::vector<H> h;
  H& at(int a, int b) { return h[static_cast<size_t>(a + n0 * b)]; }
};

Net homogeneous_net(const Patch& p) {
  Net net;
  net.n0 = p.num_points(0);
  for (int a = 0; a < p.num_points(); ++a)
    net.h.emplace_back(p.weight(a) * p.control_point(a).x(), p.weight(a) * p.control_point(a).y(),
                       p.weight(a) * p.control_point(a).z(), p.weight(a));
  return net;
}

// Replaces the given copies of one control point (from different faces) by their mean, after
// checking that they agree.
void unify(const std::vector<H*>& copies, double tolerance) {
  H mean = H::Zero();
  for (const H* c : copies) mean += *c / static_cast<double>(copies.size());
  for (const H* c : copies) {
    const double gap = (c->head<3>() / c->w() - mean.head<3>() / mean.w()).norm();
    if (gap > tolerance || std::abs(c->w() - mean.w()) > 1e-12 * mean.w()) {
      std::ostringstream msg;
      msg << "coons_volume: neighbouring faces do not share their edges (gap " << gap
          << ", weights " << c->w() << " and " << mean.w() << ")";
      throw std::invalid_argument(msg.str());
    }
  }
  for (H* c : copies) *c = mean;
}

}  // namespace

Patch coons_volume(const std::array<Patch, 6>& faces, double tolerance) {
  for (const Patch& f : faces)
    if (f.param_dim() != 2 || f.param_min(0) != 0.0 || f.param_max(0) != 1.0 ||
        f.param_min(1) != 0.0 || f.param_max(1) != 1.0)
      throw std::invalid_argument("coons_volume: six surface patches over [0, 1]^2 are needed");
  const KnotVector &U = faces[2].knots(0), &V = faces[0].knots(0), &W = faces[0].knots(1);
  auto same = [](const KnotVector& a, const KnotVector& b) {
    return a.degree() == b.degree() && a.values() == b.values();
  };
  if (!same(faces[3].knots(0), U) || !same(faces[4].knots(0), U) || !same(faces[5].knots(0), U) ||
      !same(faces[1].knots(0), V) || !same(faces[4].knots(1), V) || !same(faces[5].knots(1), V) ||
      !same(faces[1].knots(1), W) || !same(faces[2].knots(1), W) || !same(faces[3].knots(1), W))
    throw std::invalid_argument(
        "coons_volume: faces must have the same knot vectors along shared directions");
  std::array<Net, 2> Fu{homogeneous_net(faces[0]), homogeneous_net(faces[1])};
  std::array<Net, 2> Fv{homogeneous_net(faces[2]), homogeneous_net(faces[3])};
  std::array<Net, 2> Fw{homogeneous_net(faces[4]), homogeneous_net(faces[5])};
  const int nu = U.num_basis(), nv = V.num_basis(), nw = W.num_basis();
  auto last = [](int end, int n) { return end == 0 ? 0 : n - 1; };
  // Corners (three faces each), then the interior points of the twelve edges (two faces each).
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b)
      for (int c = 0; c < 2; ++c) {
        const int i = last(a, nu), j = last(b, nv), k = last(c, nw);
        unify({&Fu[a].at(j, k), &Fv[b].at(i, k), &Fw[c].at(i, j)}, tolerance);
      }
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b) {
      for (int i = 1; i + 1 < nu; ++i)  // along u at v = a, w = b
        unify({&Fv[a].at(i, last(b, nw)), &Fw[b].at(i, last(a, nv))}, tolerance);
      for (int j = 1; j + 1 < nv; ++j)  // along v at u = a, w = b
        unify({&Fu[a].at(j, last(b, nw)), &Fw[b].at(last(a, nu), j)}, tolerance);
      for (int k = 1; k + 1 < nw; ++k)  // along w at u = a, v = b
        unify({&Fu[a].at(last(b, nv), k), &Fv[b].at(last(a, nu), k)}, tolerance);
    }
  const std::vector<double> gu = greville_abscissae(U), gv = greville_abscissae(V),
                            gw = greville_abscissae(W);
  bool rational = false;
  for (const Patch& f : faces) rational = rational || f.is_rational();
  std::vector<Eigen::Vector3d> points;
  std::vector<double> weights;
  for (int k = 0; k < nw; ++k)
    for (int j = 0; j < nv; ++j)
      for (int i = 0; i < nu; ++i) {
        const std::array<double, 2> lu{1 - gu[static_cast<size_t>(i)], gu[static_cast<size_t>(i)]},
            lv{1 - gv[static_cast<size_t>(j)], gv[static_cast<size_t>(j)]},
            lw{1 - gw[static_cast<size_t>(k)], gw[static_cast<size_t>(k)]};
        H p = H::Zero();
        for (int a = 0; a < 2; ++a) {
          p += lu[a] * Fu[a].at(j, k) + lv[a] * Fv[a].at(i, k) + lw[a] * Fw[a].at(i, j);
          for (int b = 0; b < 2; ++b) {
            p -= lu[a] * lv[b] * Fu[a].at(last(b, nv), k);  // edges along w
            p -= lv[a] * lw[b] * Fv[a].at(i, last(b, nw));  // edges along u
            p -= lu[a] * lw[b] * Fu[a].at(j, last(b, nw));  // edges along v
            for (int c = 0; c < 2; ++c)
              p += lu[a] * lv[b] * lw[c] * Fu[a].at(last(b, nv), last(c, nw));
          }
        }
        if (!(p.w() > 0.0))
          throw std::invalid_argument("coons_volume: a blended weight is not positive");
        points.emplace_back(p.head<3>() / p.w());
        weights.push_back(p.w());
      }
  if (!rational) weights.clear();
  return Patch({U, V, W}, points, weights);
}

}  // namespace isospring::geometry
