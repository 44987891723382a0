// Line quadrature of cut rectangles: Gauss points along lines clipped to circles in closed form.
#include "immersed_lines.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "isospring/nurbs/quadrature.hpp"

namespace isospring::geometry::detail {

namespace {

using Interval = std::pair<double, double>;

// Removes (a, b) from every interval of the list.
void subtract(std::vector<Interval>& parts, double a, double b) {
  std::vector<Interval> out;
  for (const auto& [lo, hi] : parts) {
    if (b <= lo || a >= hi) {
      out.emplace_back(lo, hi);
      continue;
    }
    if (a > lo) out.emplace_back(lo, a);
    if (b < hi) out.emplace_back(b, hi);
  }
  parts = std::move(out);
}

void intersect(std::vector<Interval>& parts, double a, double b) {
  std::vector<Interval> out;
  for (const auto& [lo, hi] : parts)
    if (std::max(lo, a) < std::min(hi, b)) out.emplace_back(std::max(lo, a), std::min(hi, b));
  parts = std::move(out);
}

// Pieces of the line {x_outer = t, lo <= x_inner <= hi} on the part side of every circle.
std::vector<Interval> line_pieces(double t, double lo, double hi, int outer,
                                  const std::vector<LineCircle>& circles) {
  const int inner = 1 - outer;
  std::vector<Interval> parts{{lo, hi}};
  std::vector<double> cuts;
  for (const auto& c : circles) {
    const double d = t - c.centre[outer];
    const double h2 = c.radius * c.radius - d * d;
    if (c.breaks_only) {
      if (h2 > 0) {
        cuts.push_back(c.centre[inner] - std::sqrt(h2));
        cuts.push_back(c.centre[inner] + std::sqrt(h2));
      }
    } else if (c.part_inside) {
      if (h2 <= 0) return {};
      const double h = std::sqrt(h2);
      intersect(parts, c.centre[inner] - h, c.centre[inner] + h);
    } else if (h2 > 0) {
      const double h = std::sqrt(h2);
      subtract(parts, c.centre[inner] - h, c.centre[inner] + h);
    }
  }
  for (double cut : cuts) {
    std::vector<Interval> split;
    for (const auto& [a, b] : parts) {
      if (cut > a && cut < b) {
        split.emplace_back(a, cut);
        split.emplace_back(cut, b);
      } else {
        split.emplace_back(a, b);
      }
    }
    parts = std::move(split);
  }
  return parts;
}

bool contains(const Rectangle& rect, const Eigen::Vector2d& x, double tolerance) {
  return (x.array() >= rect.lo.array() - tolerance).all() &&
         (x.array() <= rect.hi.array() + tolerance).all();
}

// A direction is usable for the outer integral when no circle has a tangent along the lines
// (an extreme point in the outer direction) in the closed rectangle: there the line's limits
// behave like a square root and Gauss rules lose their exponential convergence.
bool outer_direction_usable(const Rectangle& rect, const std::vector<LineCircle>& circles,
                            int outer) {
  const double tolerance = 1e-12 * (rect.hi - rect.lo).norm();
  for (const auto& c : circles)
    for (double s : {-1.0, 1.0}) {
      Eigen::Vector2d extreme = c.centre;
      extreme[outer] += s * c.radius;
      if (contains(rect, extreme, tolerance)) return false;
    }
  return true;
}

// Outer-coordinate values where the topology of the line pieces changes.
std::vector<double> outer_breaks(const Rectangle& rect, const std::vector<LineCircle>& circles,
                                 int outer) {
  const int inner = 1 - outer;
  std::vector<double> breaks{rect.lo[outer], rect.hi[outer]};
  const auto add = [&](double t) {
    if (t > rect.lo[outer] && t < rect.hi[outer]) breaks.push_back(t);
  };
  for (const auto& c : circles) {
    for (double s : {rect.lo[inner], rect.hi[inner]}) {
      const double d = s - c.centre[inner], h2 = c.radius * c.radius - d * d;
      if (h2 < 0) continue;
      add(c.centre[outer] - std::sqrt(h2));
      add(c.centre[outer] + std::sqrt(h2));
    }
    add(c.centre[outer] - c.radius);
    add(c.centre[outer] + c.radius);
  }
  for (size_t a = 0; a < circles.size(); ++a)
    for (size_t b = a + 1; b < circles.size(); ++b)
      for (const auto& x : circle_intersections(circles[a], circles[b])) add(x[outer]);
  std::sort(breaks.begin(), breaks.end());
  breaks.erase(std::unique(breaks.begin(), breaks.end()), breaks.end());
  return breaks;
}

// Gauss points needed across lines on [a, b]: the line limits are analytic except at the
// circles' tangent points t_b (square-root branch points) outside the interval, so Gauss with n
// points converges like rho^(-2n), rho = s + sqrt(s^2 - 1), s = |t_b - mid| / half-length
// (Bernstein ellipse through the nearest branch point). Enough points for 1e-16, at least
// `minimum`; 0 when the interval is too close to a tangent (s < 1.5: the caller bisects).
int outer_points(double a, double b, const std::vector<LineCircle>& circles, int outer,
                 int minimum) {
  const double mid = 0.5 * (a + b), half = 0.5 * (b - a);
  double s = 1e300;
  for (const auto& c : circles)
    for (double sign : {-1.0, 1.0}) {
      const double t = c.centre[outer] + sign * c.radius;
      if (t > a && t < b) continue;  // the circle does not bound lines on this piece
      s = std::min(s, std::abs(t - mid) / half);
    }
  if (s < 1.5) return 0;
  const double rho = s + std::sqrt(s * s - 1);
  const int needed = static_cast<int>(std::ceil(std::log(1e16) / (2 * std::log(rho))));
  return std::max(minimum, needed);
}

// False (nothing added) when a piece lies too close to a tangent; the caller bisects.
bool line_rule(const Rectangle& rect, const std::vector<LineCircle>& circles, int outer,
               const nurbs::GaussRule& gauss, bool force, PlaneRule& rule) {
  const int inner = 1 - outer;
  const std::vector<double> breaks = outer_breaks(rect, circles, outer);
  std::vector<int> counts;
  for (size_t k = 0; k + 1 < breaks.size(); ++k) {
    const int n = outer_points(breaks[k], breaks[k + 1], circles, outer,
                               static_cast<int>(gauss.points.size()));
    if (n == 0 && !force) return false;
    counts.push_back(n == 0 ? 30 : n);
  }
  for (size_t k = 0; k + 1 < breaks.size(); ++k) {
    const double a = breaks[k], b = breaks[k + 1];
    const nurbs::GaussRule across = nurbs::gauss_legendre(counts[k]);
    for (size_t q = 0; q < across.points.size(); ++q) {
      const double t = 0.5 * (a + b) + 0.5 * (b - a) * across.points[q];
      const double wt = 0.5 * (b - a) * across.weights[q];
      for (const auto& [lo, hi] : line_pieces(t, rect.lo[inner], rect.hi[inner], outer, circles))
        for (size_t r = 0; r < gauss.points.size(); ++r) {
          Eigen::Vector2d x;
          x[outer] = t;
          x[inner] = 0.5 * (lo + hi) + 0.5 * (hi - lo) * gauss.points[r];
          rule.points.push_back(x);
          rule.weights.push_back(wt * 0.5 * (hi - lo) * gauss.weights[r]);
        }
    }
  }
  return true;
}

void cut_rule(const Rectangle& rect, const std::vector<LineCircle>& circles,
              const nurbs::GaussRule& gauss, int depth, std::string& warning, PlaneRule& rule) {
  std::vector<LineCircle> crossing;
  for (const auto& c : circles) {
    const Overlap o = circle_overlap(rect, c);
    if (o == Overlap::kNone && !c.breaks_only) return;
    if (o == Overlap::kPartial) crossing.push_back(c);
  }
  if (crossing.empty()) {  // a rectangle: the tensor Gauss rule
    for (size_t b = 0; b < gauss.points.size(); ++b)
      for (size_t a = 0; a < gauss.points.size(); ++a) {
        const Eigen::Vector2d t(gauss.points[a], gauss.points[b]);
        rule.points.push_back(0.5 * (rect.lo + rect.hi) +
                              0.5 * (rect.hi - rect.lo).cwiseProduct(t));
        rule.weights.push_back(0.25 * (rect.hi - rect.lo).prod() * gauss.weights[a] *
                               gauss.weights[b]);
      }
    return;
  }
  for (int outer : {0, 1})
    if (outer_direction_usable(rect, crossing, outer) &&
        line_rule(rect, crossing, outer, gauss, depth == 0, rule))
      return;
  if (depth == 0) {
    warning = "a cut cell needed more bisections than allowed for tangent-free line directions";
    line_rule(rect, crossing, 0, gauss, true, rule);
    return;
  }
  const Eigen::Vector2d mid = 0.5 * (rect.lo + rect.hi);
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) {
      Rectangle sub;
      sub.lo = {i ? mid.x() : rect.lo.x(), j ? mid.y() : rect.lo.y()};
      sub.hi = {i ? rect.hi.x() : mid.x(), j ? rect.hi.y() : mid.y()};
      cut_rule(sub, crossing, gauss, depth - 1, warning, rule);
    }
}

}  // namespace

Overlap circle_overlap(const Rectangle& rect, const LineCircle& circle) {
  const Eigen::Vector2d nearest = circle.centre.cwiseMax(rect.lo).cwiseMin(rect.hi);
  const double near = (nearest - circle.centre).norm();
  const Eigen::Vector2d far_corner =
      (circle.centre - rect.lo).cwiseAbs().cwiseMax((circle.centre - rect.hi).cwiseAbs());
  const double far = far_corner.norm();
  if (circle.part_inside) {
    if (far <= circle.radius) return Overlap::kFull;
    if (near >= circle.radius) return Overlap::kNone;
  } else {
    if (near >= circle.radius) return Overlap::kFull;
    if (far <= circle.radius) return Overlap::kNone;
  }
  return Overlap::kPartial;
}

bool on_part_side(const Eigen::Vector2d& x, const std::vector<LineCircle>& circles,
                  double tolerance) {
  for (const auto& c : circles) {
    if (c.breaks_only) continue;
    const double d = (x - c.centre).norm() - c.radius;
    if (c.part_inside ? d > -tolerance : d < tolerance) return false;
  }
  return true;
}

PlaneRule cut_rectangle_rule(const Rectangle& rect, const std::vector<LineCircle>& circles,
                             int points, std::string& warning, int max_depth) {
  PlaneRule rule;
  cut_rule(rect, circles, nurbs::gauss_legendre(points), max_depth, warning, rule);
  return rule;
}

std::vector<Eigen::Vector2d> circle_intersections(const LineCircle& a, const LineCircle& b) {
  const Eigen::Vector2d d = b.centre - a.centre;
  const double l = d.norm();
  if (l == 0 || l > a.radius + b.radius || l < std::abs(a.radius - b.radius)) return {};
  const double x = (l * l + a.radius * a.radius - b.radius * b.radius) / (2 * l);
  const double h = std::sqrt(std::max(0.0, a.radius * a.radius - x * x));
  const Eigen::Vector2d e = d / l, n(-e.y(), e.x());
  const Eigen::Vector2d base = a.centre + x * e;
  if (h == 0) return {base};
  return {base + h * n, base - h * n};
}

}  // namespace isospring::geometry::detail
