// The ring construction of the planar split, shared with the block split of solids (see
// planar_split_parts.hpp).
#include "planar_split_parts.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "isospring/geometry/construction.hpp"
#include "isospring/geometry/coons.hpp"
#include "isospring/nurbs/quadrature.hpp"
#include "isospring/nurbs/refine.hpp"

namespace isospring::geometry {

namespace planar_split_detail {

using Eigen::Vector3d;
using nurbs::KnotVector;
using nurbs::Patch;

[[noreturn]] void refuse(const std::string& why) {
  throw std::invalid_argument(why);
}

Vector3d start_point(const Patch& c) {
  return c.point({c.param_min(0), 0, 0});
}
Vector3d end_point(const Patch& c) {
  return c.point({c.param_max(0), 0, 0});
}

// Points along the loop, `per_curve` per curve from its start (its end is the next one's start).
std::vector<Vector3d> loop_samples(const Loop& loop, int per_curve) {
  std::vector<Vector3d> points;
  for (const Patch& c : loop)
    for (int k = 0; k < per_curve; ++k)
      points.push_back(
          c.point({c.param_min(0) + (c.param_max(0) - c.param_min(0)) * k / per_curve, 0.0, 0.0}));
  return points;
}

double signed_area(const std::vector<Vector3d>& polygon) {
  double area = 0.0;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Vector3d& a = polygon[i];
    const Vector3d& b = polygon[(i + 1) % polygon.size()];
    area += a.x() * b.y() - b.x() * a.y();
  }
  return area / 2.0;
}

// Area and first moments (A, A cx, A cy) of the region a loop encloses, signed by the loop's
// sense, from the exact curves (Green: A = 1/2 oint x dy - y dx, A cx = 1/2 oint x^2 dy,
// A cy = -1/2 oint y^2 dx), Gauss on every knot span: to round-off for a circle, so the cuts of a
// circular hole are symmetric (a polygon of samples is not).
Vector3d moments(const Loop& loop) {
  const nurbs::GaussRule rule = nurbs::gauss_legendre(12);
  double area = 0.0, mx = 0.0, my = 0.0;
  for (const Patch& c : loop) {
    const std::vector<double> breaks = c.knots(0).unique();
    for (size_t e = 0; e + 1 < breaks.size(); ++e)
      for (size_t g = 0; g < rule.points.size(); ++g) {
        const double h = (breaks[e + 1] - breaks[e]) / 2.0;
        const double t = breaks[e] + (rule.points[g] + 1.0) * h;
        const nurbs::PatchDerivatives d = c.derivatives({t, 0, 0});
        const double w = rule.weights[g] * h;
        const Vector3d& x = d.point;
        const Vector3d dx = d.first.col(0);
        area += w * (x.x() * dx.y() - x.y() * dx.x()) / 2.0;
        mx += w * x.x() * x.x() * dx.y() / 2.0;
        my -= w * x.y() * x.y() * dx.x() / 2.0;
      }
  }
  return {area, mx, my};
}

Vector3d centroid(const Loop& loop) {
  const Vector3d m = moments(loop);
  return {m.y() / m.x(), m.z() / m.x(), 0.0};
}

double enclosed_area(const Loop& loop) {
  return std::abs(moments(loop).x());
}

// The loop running counter-clockwise (the ring construction below relies on it).
Loop counter_clockwise(const Loop& loop) {
  if (signed_area(loop_samples(loop, 16)) > 0.0) return loop;
  Loop reversed;
  for (auto it = loop.rbegin(); it != loop.rend(); ++it)
    reversed.push_back(reverse_direction(*it, 0));
  return reversed;
}

// A curve that is a straight segment: every control point on its chord (B-spline convex hull).
bool straight(const Patch& c, double tolerance) {
  const Vector3d a = start_point(c), b = end_point(c);
  const double length = (b - a).norm();
  if (length <= tolerance) return false;
  const Vector3d t = (b - a) / length;
  for (const Vector3d& x : c.control_points()) {
    const double s = (x - a).dot(t);
    if ((x - a - s * t).norm() > tolerance || s < -tolerance || s > length + tolerance)
      return false;
  }
  return true;
}

// The segment a -> b with the given knots, parametrised linearly (control points at the
// Greville abscissae), weights 1: the side shared with a neighbouring rectangle.
// a + g (b - a), exactly b at g = 1: shared sides must have bitwise equal control points.
double lerp(double a, double b, double g) {
  return g == 1.0 ? b : a + g * (b - a);
}

Vector3d lerp(const Vector3d& a, const Vector3d& b, double g) {
  return {lerp(a.x(), b.x(), g), lerp(a.y(), b.y(), g), lerp(a.z(), b.z(), g)};
}

Patch line(const Vector3d& a, const Vector3d& b, const KnotVector& knots) {
  std::vector<Vector3d> points;
  for (double g : greville_abscissae(knots)) points.push_back(lerp(a, b, g));
  return Patch({knots}, points);
}

// The rectangle [x0, x1] x [y0, y1] with the given knots along x and y (weights 1).
Patch rectangle(double x0, double x1, double y0, double y1, const KnotVector& ku,
                const KnotVector& kv) {
  std::vector<Vector3d> points;
  for (double gv : greville_abscissae(kv))
    for (double gu : greville_abscissae(ku))
      points.emplace_back(lerp(x0, x1, gu), lerp(y0, y1, gv), 0.0);
  return Patch({ku, kv}, points);
}

double control_polygon_length(const Patch& c) {
  double length = 0.0;
  for (int i = 0; i + 1 < c.num_points(); ++i)
    length += (c.control_point(i + 1) - c.control_point(i)).norm();
  return length;
}

// a followed by b (a's end is b's start) as one curve over [0, 1] with a C0 knot at the joint;
// each part gets a parameter length proportional to its control polygon, so the speed stays
// roughly even. b's weights are scaled (which leaves it unchanged) to meet a's at the joint.
Patch join(Patch a, Patch b) {
  const int p = std::max(a.degree(0), b.degree(0));
  a = nurbs::elevate_degree(a, 0, p - a.degree(0));
  b = nurbs::elevate_degree(b, 0, p - b.degree(0));
  const double la = control_polygon_length(a), lb = control_polygon_length(b);
  const double total = la + lb;
  std::vector<double> knots;
  const KnotVector& ka = a.knots(0);
  const KnotVector& kb = b.knots(0);
  for (int i = 0; i + 1 < ka.size(); ++i)
    knots.push_back((ka[i] - ka.first()) / (ka.last() - ka.first()) * la / total);
  for (int i = p + 1; i < kb.size(); ++i)
    knots.push_back((la + (kb[i] - kb.first()) / (kb.last() - kb.first()) * lb) / total);
  knots.back() = 1.0;
  std::vector<Vector3d> points = a.control_points();
  std::vector<double> weights = a.weights();
  const double scale = a.weights().back() / b.weights().front();
  for (int i = 1; i < b.num_points(); ++i) {
    points.push_back(b.control_point(i));
    weights.push_back(scale * b.weight(i));
  }
  return Patch({KnotVector(p, knots, "joined boundary curve")}, points, weights);
}

double wrap(double angle) {
  while (angle > M_PI) angle -= 2.0 * M_PI;
  while (angle <= -M_PI) angle += 2.0 * M_PI;
  return angle;
}

struct LoopPosition {
  int curve = 0;
  double t = 0.0;
};

// Where the ray from `center` through `toward` crosses the (counter-clockwise, star-shaped)
// loop: the sampled angle about the centre brackets the ray, bisection pins it to round-off.
LoopPosition ray_crossing(const Loop& loop, const Vector3d& center, const Vector3d& toward,
                          const std::string& what) {
  const double theta = std::atan2(toward.y() - center.y(), toward.x() - center.x());
  auto offset = [&](const Patch& c, double t) {
    const Vector3d x = c.point({t, 0, 0});
    return wrap(std::atan2(x.y() - center.y(), x.x() - center.x()) - theta);
  };
  constexpr int kSamples = 64;
  for (size_t i = 0; i < loop.size(); ++i) {
    const Patch& c = loop[i];
    const double a = c.param_min(0), b = c.param_max(0);
    for (int k = 0; k < kSamples; ++k) {
      double t0 = a + (b - a) * k / kSamples, t1 = a + (b - a) * (k + 1) / kSamples;
      const double f0 = offset(c, t0), f1 = offset(c, t1);
      if (!(f0 <= 0.0 && f1 > 0.0 && f1 - f0 < M_PI / 2)) continue;
      for (int n = 0; n < 200 && t1 - t0 > 1e-15 * (b - a); ++n) {
        const double m = (t0 + t1) / 2;
        (offset(c, m) <= 0.0 ? t0 : t1) = m;
      }
      // A cut within 1e-9 (of the parameter range) of a knot is moved onto it: the point stays on
      // the curve, and no sliver of an element is left beside the knot.
      double t = (t0 + t1) / 2;
      for (double k : c.knots(0).unique())
        if (std::abs(t - k) <= 1e-9 * (b - a)) t = k;
      return {static_cast<int>(i), t};
    }
  }
  refuse(what + " is not star-shaped about its centre (a ray from the centre does not cross it)");
}

// Part [t0, t1] of a curve (t0 < t1 inside its range, or its ends).
Patch piece(const Patch& c, double t0, double t1) {
  const double a = c.param_min(0), b = c.param_max(0), eps = 1e-10 * (b - a);
  Patch result = c;
  if (t0 > a + eps) result = split_patch(result, 0, t0).second;
  if (t1 < b - eps) result = split_patch(result, 0, t1).first;
  return result;
}

// The loop from position `from` to position `to` (counter-clockwise) as one curve.
Patch sub_loop(const Loop& loop, LoopPosition from, LoopPosition to) {
  std::vector<Patch> pieces;
  int i = from.curve;
  double t = from.t;
  for (size_t visited = 0; visited <= loop.size(); ++visited) {
    const Patch& c = loop[static_cast<size_t>(i)];
    const double eps = 1e-10 * (c.param_max(0) - c.param_min(0));
    if (i == to.curve && (to.t > t + eps || (visited > 0 && to.t >= t))) {
      if (to.t > t + eps) pieces.push_back(piece(c, t, to.t));
      break;
    }
    if (c.param_max(0) > t + eps) pieces.push_back(piece(c, t, c.param_max(0)));
    i = (i + 1) % static_cast<int>(loop.size());
    t = loop[static_cast<size_t>(i)].param_min(0);
  }
  if (pieces.empty()) refuse("two cut points of a loop coincide");
  Patch result = pieces.front();
  for (size_t k = 1; k < pieces.size(); ++k) result = join(result, pieces[k]);
  return result;
}

// Coordinates within `tolerance` merged (sorted, first of each cluster kept).
std::vector<double> merged(std::vector<double> values, double tolerance) {
  std::sort(values.begin(), values.end());
  std::vector<double> result;
  for (double v : values)
    if (result.empty() || v - result.back() > tolerance) result.push_back(v);
  return result;
}

int grid_index(const std::vector<double>& grid, double v, double tolerance) {
  for (size_t i = 0; i < grid.size(); ++i)
    if (std::abs(grid[i] - v) <= tolerance) return static_cast<int>(i);
  return -1;
}

bool inside_polygon(const std::vector<Vector3d>& polygon, const Vector3d& x) {
  bool inside = false;
  for (size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
    const Vector3d &a = polygon[i], &b = polygon[j];
    if ((a.y() > x.y()) != (b.y() > x.y()) &&
        x.x() < (b.x() - a.x()) * (x.y() - a.y()) / (b.y() - a.y()) + a.x())
      inside = !inside;
  }
  return inside;
}

std::string hole_name(size_t h) {
  return "hole " + std::to_string(h + 1);
}

// Cuts the ring's loop on the rays through the corners of its square (grid values).
void cut_quarters(Ring& ring, double x0, double x1, double y0, double y1, const std::string& what) {
  const Vector3d tr(x1, y1, 0), tl(x0, y1, 0), bl(x0, y0, 0), br(x1, y0, 0);
  const LoopPosition p_tr = ray_crossing(ring.loop, ring.center, tr, what);
  const LoopPosition p_tl = ray_crossing(ring.loop, ring.center, tl, what);
  const LoopPosition p_bl = ray_crossing(ring.loop, ring.center, bl, what);
  const LoopPosition p_br = ray_crossing(ring.loop, ring.center, br, what);
  ring.above = reverse_direction(sub_loop(ring.loop, p_tr, p_tl), 0);
  ring.left = reverse_direction(sub_loop(ring.loop, p_tl, p_bl), 0);
  ring.below = sub_loop(ring.loop, p_bl, p_br);
  ring.right = sub_loop(ring.loop, p_br, p_tr);
}

// Ruled patch between a quarter of the loop and a side of the square, right-handed.
Patch ring_patch(const Patch& quarter, const Patch& side, bool hole, const std::string& what) {
  const Patch ruled_patch = hole ? ruled(quarter, side) : ruled(side, quarter);
  try {
    const Patch patch = with_positive_jacobian(ruled_patch);
    if (!(jacobian_range(patch, 6).min > 0.0)) throw std::runtime_error("degenerate");
    return patch;
  } catch (const std::runtime_error&) {
    refuse("a ring patch around " + what +
           " folds (its Jacobian changes sign): the loop is too far from a circle for a square "
           "ring");
  }
}

KnotVector plain_knots(int degree) {
  std::vector<double> k(static_cast<size_t>(degree) + 1, 0.0);
  k.insert(k.end(), static_cast<size_t>(degree) + 1, 1.0);
  return KnotVector(degree, k);
}

KnotVector common_knots(const std::vector<Patch*>& quarters, int degree) {
  const KnotVector plain = plain_knots(degree);
  if (quarters.empty()) return plain;
  std::vector<Patch> curves{line(Vector3d::Zero(), Vector3d::UnitX(), plain)};
  for (Patch* q : quarters) curves.push_back(*q);
  const std::vector<Patch> same = make_compatible(curves);
  for (size_t k = 0; k < quarters.size(); ++k) *quarters[k] = same[k + 1];
  return same[0].knots(0);
}

void prepare_ring(Ring& ring) {
  const std::vector<Vector3d> samples = loop_samples(ring.loop, 64);
  ring.center = centroid(ring.loop);
  double nearest = std::numeric_limits<double>::infinity();
  for (const Vector3d& x : samples) {
    ring.extent = std::max(
        {ring.extent, std::abs(x.x() - ring.center.x()), std::abs(x.y() - ring.center.y())});
    nearest = std::min(nearest, (x - ring.center).norm());
  }
  if (!ring.hole) ring.extent = nearest;  // the square's half side is half the inner radius
}

// The stages the planar and the block split share, in the order they run.

void share_squares_in_line(const std::vector<Ring*>& rings,
                           const std::function<bool(size_t, size_t)>& in_line) {
  // Each pass carries the smaller square one ring further along a chain of rings in line.
  for (size_t pass = 0; pass < rings.size(); ++pass)
    for (size_t h = 0; h < rings.size(); ++h)
      for (size_t k = 0; k < rings.size(); ++k)
        if (k != h && in_line(h, k))
          rings[h]->half = rings[k]->half = std::min(rings[h]->half, rings[k]->half);
}

void check_ring_room(const Ring& ring, const std::string& name, const std::string& bounds) {
  if (ring.extent > 0.9 * ring.half) {
    std::ostringstream why;
    why.precision(3);
    why << name << " (half size " << ring.extent << ") is too close to " << bounds
        << " or to another hole for a ring of patches (room: a square of half side " << ring.half
        << ")";
    refuse(why.str());
  }
}

void place_ring(Ring& ring, const std::vector<double>& gx, const std::vector<double>& gy,
                double tolerance, const std::string& what, const std::string& cut) {
  ring.col = grid_index(gx, ring.center.x() - ring.half, tolerance);
  ring.row = grid_index(gy, ring.center.y() - ring.half, tolerance);
  if (ring.col + 1 != grid_index(gx, ring.center.x() + ring.half, tolerance) ||
      ring.row + 1 != grid_index(gy, ring.center.y() + ring.half, tolerance))
    refuse("a cut " + cut + " crosses the square around " + what);
}

Square grid_square(const Ring& ring, const std::vector<double>& gx, const std::vector<double>& gy) {
  const size_t i = static_cast<size_t>(ring.col), j = static_cast<size_t>(ring.row);
  return {gx[i], gx[i + 1], gy[j], gy[j + 1]};
}

int ring_degree(const std::vector<Ring*>& rings) {
  int degree = 2;
  for (const Ring* ring : rings)
    for (const Patch* q : {&ring->below, &ring->right, &ring->above, &ring->left})
      degree = std::max(degree, q->degree(0));
  return degree;
}

void add_quarters_along(Ring& ring, bool x_axis, bool y_axis, int i,
                        std::vector<Patch*>& quarters) {
  if (x_axis && ring.col == i) {
    quarters.push_back(&ring.below);
    quarters.push_back(&ring.above);
  }
  if (y_axis && ring.row == i) {
    quarters.push_back(&ring.left);
    quarters.push_back(&ring.right);
  }
}

std::vector<Patch> square_ring_patches(const Ring& ring, const Square& square,
                                       const KnotVector& along_x, const KnotVector& along_y,
                                       const std::string& what) {
  const Vector3d bl(square.x0, square.y0, 0), br(square.x1, square.y0, 0),
      tl(square.x0, square.y1, 0), tr(square.x1, square.y1, 0);
  // A braced list is evaluated in order: the first patch that folds is the one refused.
  return {ring_patch(ring.below, line(bl, br, along_x), ring.hole, what),
          ring_patch(ring.right, line(br, tr, along_y), ring.hole, what),
          ring_patch(ring.above, line(tl, tr, along_x), ring.hole, what),
          ring_patch(ring.left, line(bl, tl, along_y), ring.hole, what)};
}

}  // namespace planar_split_detail

}  // namespace isospring::geometry
