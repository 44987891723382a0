// Boundary points of implicit shapes on the exact straight sides and arcs, one Gauss rule per
// piece between grid lines (so that every piece lies in one cell, where the basis is polynomial).
#include <algorithm>
#include <cmath>

#include "immersed_lines.hpp"
#include "isospring/geometry/immersed_implicit.hpp"
#include "isospring/nurbs/quadrature.hpp"

namespace isospring::geometry::detail {

namespace {

struct Segment2 {
  Eigen::Vector2d point, normal;
  double weight;
  int face;  // numbering of the 2D cross-section: sides 0..3, circle k at 4 + k
};

std::vector<LineCircle> circles_of(const ImplicitShape& shape) {
  std::vector<LineCircle> out;
  for (const auto& c : shape.circles) out.push_back({c.centre, c.radius, c.part_inside});
  return out;
}

bool in_box(const Eigen::Vector2d& x, const ImplicitShape& shape, double tolerance) {
  return (x.array() > shape.box_min.head<2>().array() + tolerance).all() &&
         (x.array() < shape.box_max.head<2>().array() - tolerance).all();
}

void sort_unique(std::vector<double>& v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
}

// The box side x_d = box_{min,max}[d] where it lies on the part side of every circle.
void straight_side(const ImplicitShape& shape, const std::vector<LineCircle>& circles,
                   const std::array<std::vector<double>, 3>& lines, int d, int end,
                   const nurbs::GaussRule& gauss, double tolerance, std::vector<Segment2>& out) {
  const int o = 1 - d;
  const double fixed = end ? shape.box_max[d] : shape.box_min[d];
  const double lo = shape.box_min[o], hi = shape.box_max[o];
  std::vector<double> breaks{lo, hi};
  for (double l : lines[static_cast<size_t>(o)])
    if (l > lo && l < hi) breaks.push_back(l);
  for (const auto& c : circles) {
    const double h2 = c.radius * c.radius - (fixed - c.centre[d]) * (fixed - c.centre[d]);
    if (h2 <= 0) continue;
    for (double s : {-1.0, 1.0}) {
      const double t = c.centre[o] + s * std::sqrt(h2);
      if (t > lo && t < hi) breaks.push_back(t);
    }
  }
  sort_unique(breaks);
  Eigen::Vector2d normal = Eigen::Vector2d::Zero();
  normal[d] = end ? 1.0 : -1.0;
  for (size_t k = 0; k + 1 < breaks.size(); ++k) {
    const double a = breaks[k], b = breaks[k + 1];
    Eigen::Vector2d mid;
    mid[d] = fixed;
    mid[o] = 0.5 * (a + b);
    if (!on_part_side(mid, circles, tolerance)) continue;
    for (size_t q = 0; q < gauss.points.size(); ++q) {
      Eigen::Vector2d x = mid;
      x[o] = 0.5 * (a + b) + 0.5 * (b - a) * gauss.points[q];
      out.push_back({x, normal, 0.5 * (b - a) * gauss.weights[q], 2 * d + end});
    }
  }
}

// Angles in [0, 2 pi) where circle c crosses a grid line, a box side or another circle.
std::vector<double> arc_breaks(const ImplicitShape& shape, const std::vector<LineCircle>& circles,
                               const std::array<std::vector<double>, 3>& lines, size_t k) {
  const LineCircle& c = circles[k];
  std::vector<double> breaks{0.0, 2 * M_PI};
  const auto add = [&](double t) {
    t = std::fmod(t, 2 * M_PI);
    if (t < 0) t += 2 * M_PI;
    if (t > 0 && t < 2 * M_PI) breaks.push_back(t);
  };
  for (int d = 0; d < 2; ++d) {
    std::vector<double> at = lines[static_cast<size_t>(d)];
    at.push_back(shape.box_min[d]);
    at.push_back(shape.box_max[d]);
    for (double l : at) {
      const double s = (l - c.centre[d]) / c.radius;
      if (std::abs(s) >= 1) continue;
      if (d == 0) {
        add(std::acos(s));
        add(-std::acos(s));
      } else {
        add(std::asin(s));
        add(M_PI - std::asin(s));
      }
    }
  }
  for (size_t m = 0; m < circles.size(); ++m)
    if (m != k)
      for (const auto& x : circle_intersections(c, circles[m]))
        add(std::atan2(x.y() - c.centre.y(), x.x() - c.centre.x()));
  sort_unique(breaks);
  // Pieces of at most pi / 16: the integrands are trigonometric polynomials in the angle (of the
  // basis' degree), which a Gauss rule of 2 (p + 1) points integrates to ~1e-13 on such a piece.
  std::vector<double> fine{breaks.front()};
  for (size_t k = 0; k + 1 < breaks.size(); ++k) {
    const int parts = static_cast<int>(std::ceil((breaks[k + 1] - breaks[k]) / (M_PI / 16)));
    for (int j = 1; j <= parts; ++j)
      fine.push_back(breaks[k] + (breaks[k + 1] - breaks[k]) * j / parts);
  }
  return fine;
}

void arc(const ImplicitShape& shape, const std::vector<LineCircle>& circles,
         const std::array<std::vector<double>, 3>& lines, size_t k, const nurbs::GaussRule& gauss,
         double tolerance, std::vector<Segment2>& out) {
  const LineCircle& c = circles[k];
  std::vector<LineCircle> others = circles;
  others.erase(others.begin() + static_cast<std::ptrdiff_t>(k));
  const std::vector<double> breaks = arc_breaks(shape, circles, lines, k);
  const auto at = [&](double t) {
    return Eigen::Vector2d(c.centre + c.radius * Eigen::Vector2d(std::cos(t), std::sin(t)));
  };
  for (size_t b = 0; b + 1 < breaks.size(); ++b) {
    const double t0 = breaks[b], t1 = breaks[b + 1];
    const Eigen::Vector2d mid = at(0.5 * (t0 + t1));
    if (!in_box(mid, shape, tolerance) || !on_part_side(mid, others, tolerance)) continue;
    for (size_t q = 0; q < gauss.points.size(); ++q) {
      const double t = 0.5 * (t0 + t1) + 0.5 * (t1 - t0) * gauss.points[q];
      const Eigen::Vector2d radial(std::cos(t), std::sin(t));
      out.push_back({at(t), c.part_inside ? radial : Eigen::Vector2d(-radial),
                     c.radius * 0.5 * (t1 - t0) * gauss.weights[q], 4 + static_cast<int>(k)});
    }
  }
}

}  // namespace

void add_implicit_boundary(const ImplicitShape& shape,
                           const std::array<std::vector<double>, 3>& lines, int points,
                           const std::vector<PlaneRule>& cross_section, ImmersedDomain& domain) {
  const nurbs::GaussRule gauss = nurbs::gauss_legendre(points);
  const double tolerance = 1e-12 * (shape.box_max - shape.box_min).head<2>().norm();
  const auto circles = circles_of(shape);
  std::vector<Segment2> curve;
  for (int d = 0; d < 2; ++d)
    for (int end = 0; end < 2; ++end)
      straight_side(shape, circles, lines, d, end, gauss, tolerance, curve);
  for (size_t k = 0; k < circles.size(); ++k)
    arc(shape, circles, lines, k, gauss, tolerance, curve);
  if (shape.dimension == 2) {
    for (const auto& s : curve)
      domain.boundary.push_back({Eigen::Vector3d(s.point.x(), s.point.y(), 0.0),
                                 Eigen::Vector3d(s.normal.x(), s.normal.y(), 0.0), s.weight,
                                 s.face});
    return;
  }
  // 3D: the cross-section's curve swept along z (pieces between z grid lines), and the
  // cross-section itself on the end faces z = box_min.z (face 4) and z = box_max.z (face 5).
  std::vector<double> zs{shape.box_min.z(), shape.box_max.z()};
  for (double l : lines[2])
    if (l > shape.box_min.z() && l < shape.box_max.z()) zs.push_back(l);
  sort_unique(zs);
  for (size_t k = 0; k + 1 < zs.size(); ++k)
    for (size_t q = 0; q < gauss.points.size(); ++q) {
      const double z = 0.5 * (zs[k] + zs[k + 1]) + 0.5 * (zs[k + 1] - zs[k]) * gauss.points[q];
      const double wz = 0.5 * (zs[k + 1] - zs[k]) * gauss.weights[q];
      for (const auto& s : curve)
        domain.boundary.push_back({Eigen::Vector3d(s.point.x(), s.point.y(), z),
                                   Eigen::Vector3d(s.normal.x(), s.normal.y(), 0.0), s.weight * wz,
                                   s.face < 4 ? s.face : s.face + 2});
    }
  for (int end = 0; end < 2; ++end)
    for (const PlaneRule& rule : cross_section)
      for (size_t a = 0; a < rule.points.size(); ++a)
        domain.boundary.push_back({Eigen::Vector3d(rule.points[a].x(), rule.points[a].y(),
                                                   end ? shape.box_max.z() : shape.box_min.z()),
                                   Eigen::Vector3d(0.0, 0.0, end ? 1.0 : -1.0), rule.weights[a],
                                   4 + end});
}

}  // namespace isospring::geometry::detail
