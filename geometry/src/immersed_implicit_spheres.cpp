// Immersed domains of boxes intersected with spheres (3D): cell rules along lines, sphere
// surface points as graphs over a 2D rule, box faces cut by the spheres (why: the header).
#include <algorithm>
#include <cmath>

#include "immersed_lines.hpp"
#include "immersed_spheres.hpp"
#include "isospring/nurbs/quadrature.hpp"

namespace isospring::geometry::detail {

namespace {

using Interval = std::pair<double, double>;

// Bisect until the silhouette lies this many cross-sections away (see axis_score).
constexpr double kMinScore = 0.5;

Overlap sphere_overlap(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                       const ImplicitSphere& s) {
  const double near = (s.centre.cwiseMax(lo).cwiseMin(hi) - s.centre).norm();
  const double far = (s.centre - lo).cwiseAbs().cwiseMax((s.centre - hi).cwiseAbs()).norm();
  if (s.part_inside) {
    if (far <= s.radius) return Overlap::kFull;
    if (near >= s.radius) return Overlap::kNone;
  } else {
    if (near >= s.radius) return Overlap::kFull;
    if (far <= s.radius) return Overlap::kNone;
  }
  return Overlap::kPartial;
}

// How far (in cross-sections of the cell) the spheres' silhouettes along axis d stay from where
// they cross the cell: r - sqrt(r^2 - delta^2), delta the distance of the centre from the cell's
// range along d (0 when the range holds the centre: lines touch the sphere inside the cell).
double axis_score(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                  const std::vector<ImplicitSphere>& spheres, int d) {
  const int a = (d + 1) % 3, b = (d + 2) % 3;
  const double size = std::hypot(hi[a] - lo[a], hi[b] - lo[b]);
  double score = 1e300;
  for (const auto& s : spheres) {
    const double delta = std::max({0.0, lo[d] - s.centre[d], s.centre[d] - hi[d]});
    const double gap = s.radius - std::sqrt(std::max(0.0, s.radius * s.radius - delta * delta));
    score = std::min(score, gap / size);
  }
  return score;
}

// Pieces of the line along d through (u, v) (outer coordinates) inside [lo, hi] on the part side
// of every sphere.
std::vector<Interval> line_pieces(double u, double v, double lo, double hi, int d,
                                  const std::vector<ImplicitSphere>& spheres) {
  const int a = (d + 1) % 3, b = (d + 2) % 3;
  std::vector<Interval> parts{{lo, hi}};
  for (const auto& s : spheres) {
    const double h2 = s.radius * s.radius - (u - s.centre[a]) * (u - s.centre[a]) -
                      (v - s.centre[b]) * (v - s.centre[b]);
    std::vector<Interval> out;
    const double h = std::sqrt(std::max(0.0, h2));
    for (const auto& [p, q] : parts) {
      if (s.part_inside) {
        if (h2 > 0 && std::max(p, s.centre[d] - h) < std::min(q, s.centre[d] + h))
          out.emplace_back(std::max(p, s.centre[d] - h), std::min(q, s.centre[d] + h));
      } else if (h2 <= 0 || q <= s.centre[d] - h || p >= s.centre[d] + h) {
        out.emplace_back(p, q);
      } else {
        if (p < s.centre[d] - h) out.emplace_back(p, s.centre[d] - h);
        if (q > s.centre[d] + h) out.emplace_back(s.centre[d] + h, q);
      }
    }
    parts = std::move(out);
  }
  return parts;
}

// The circle where the plane x_d = t cuts sphere s (radius 0 when it misses).
LineCircle plane_circle(const ImplicitSphere& s, int d, double t, bool part_inside,
                        bool breaks_only) {
  const int a = (d + 1) % 3, b = (d + 2) % 3;
  const double r2 = s.radius * s.radius - (t - s.centre[d]) * (t - s.centre[d]);
  return {Eigen::Vector2d(s.centre[a], s.centre[b]), std::sqrt(std::max(0.0, r2)), part_inside,
          breaks_only};
}

Eigen::Vector3d compose(int d, double t, const Eigen::Vector2d& uv) {
  Eigen::Vector3d x;
  x[d] = t;
  x[(d + 1) % 3] = uv.x();
  x[(d + 2) % 3] = uv.y();
  return x;
}

// Sphere points in the box for lines along d (the centre lies outside the box's d-range): the
// graph x_d = c_d + sigma sqrt(r^2 - rho^2) over the 2D region where it stays in the range.
void sphere_surface(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                    const std::vector<ImplicitSphere>& all, size_t k, int first_face, int d,
                    int points, std::string& warning, SphereRule& out) {
  const ImplicitSphere& s = all[k];
  const int a = (d + 1) % 3, b = (d + 2) % 3;
  const double sigma = lo[d] > s.centre[d] ? 1.0 : -1.0;
  const double near = sigma > 0 ? lo[d] : hi[d], far = sigma > 0 ? hi[d] : lo[d];
  const LineCircle reach = plane_circle(s, d, near, true, false);
  if (reach.radius == 0) return;
  std::vector<LineCircle> region{reach};
  const LineCircle beyond = plane_circle(s, d, far, false, false);
  if (beyond.radius > 0) region.push_back(beyond);
  const Rectangle rect{{lo[a], lo[b]}, {hi[a], hi[b]}};
  const PlaneRule rule = cut_rectangle_rule(rect, region, points, warning);
  for (size_t q = 0; q < rule.points.size(); ++q) {
    const Eigen::Vector2d& uv = rule.points[q];
    const double h = std::sqrt(std::max(
        0.0, s.radius * s.radius - (uv - Eigen::Vector2d(s.centre[a], s.centre[b])).squaredNorm()));
    const Eigen::Vector3d x = compose(d, s.centre[d] + sigma * h, uv);
    bool on_part = true;
    for (size_t m = 0; m < all.size(); ++m)
      if (m != k) {
        const double dist = (x - all[m].centre).norm() - all[m].radius;
        on_part = on_part && (all[m].part_inside ? dist < 0 : dist > 0);
      }
    if (!on_part || h <= 0) continue;
    const Eigen::Vector3d radial = (x - s.centre) / s.radius;
    out.surface.push_back({x, s.part_inside ? radial : Eigen::Vector3d(-radial),
                           rule.weights[q] * s.radius / h, first_face + static_cast<int>(k)});
  }
}

void cut_box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
             const std::vector<ImplicitSphere>& crossing, const std::vector<ImplicitSphere>& all,
             const std::vector<size_t>& index, int first_face, int full_points, int points,
             int depth, std::string& warning, SphereRule& out) {
  int d = 0;
  for (int e = 1; e < 3; ++e)
    if (axis_score(lo, hi, crossing, e) > axis_score(lo, hi, crossing, d)) d = e;
  if (axis_score(lo, hi, crossing, d) < kMinScore && depth > 0) {
    const Eigen::Vector3d mid = 0.5 * (lo + hi);
    for (int c = 0; c < 8; ++c) {
      Eigen::Vector3d sub_lo, sub_hi;
      for (int e = 0; e < 3; ++e) {
        const bool upper = (c >> e) & 1;
        sub_lo[e] = upper ? mid[e] : lo[e];
        sub_hi[e] = upper ? hi[e] : mid[e];
      }
      sphere_cell_rule(sub_lo, sub_hi, all, first_face, full_points, points, depth - 1, warning,
                       out);
    }
    return;
  }
  if (axis_score(lo, hi, crossing, d) <= 0) {
    warning = "a cell cut by a sphere could not be bisected to a tangent-free line direction";
    return;
  }
  const int a = (d + 1) % 3, b = (d + 2) % 3;
  std::vector<LineCircle> breaks;
  for (const auto& s : crossing)
    for (double t : {lo[d], hi[d]}) {
      const LineCircle c = plane_circle(s, d, t, true, true);
      if (c.radius > 0) breaks.push_back(c);
    }
  const Rectangle rect{{lo[a], lo[b]}, {hi[a], hi[b]}};
  const PlaneRule plane = cut_rectangle_rule(rect, breaks, points, warning);
  const nurbs::GaussRule g = nurbs::gauss_legendre(points);
  for (size_t q = 0; q < plane.points.size(); ++q)
    for (const auto& [p0, p1] :
         line_pieces(plane.points[q].x(), plane.points[q].y(), lo[d], hi[d], d, crossing))
      for (size_t r = 0; r < g.points.size(); ++r) {
        out.points.push_back(
            compose(d, 0.5 * (p0 + p1) + 0.5 * (p1 - p0) * g.points[r], plane.points[q]));
        out.weights.push_back(plane.weights[q] * 0.5 * (p1 - p0) * g.weights[r]);
      }
  for (size_t k = 0; k < crossing.size(); ++k)
    sphere_surface(lo, hi, all, index[k], first_face, d, points, warning, out);
}

}  // namespace

bool sphere_cell_rule(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                      const std::vector<ImplicitSphere>& spheres, int first_face, int points,
                      int cut_points, int depth, std::string& warning, SphereRule& out) {
  std::vector<ImplicitSphere> crossing;
  std::vector<size_t> index;
  for (size_t k = 0; k < spheres.size(); ++k) {
    const Overlap o = sphere_overlap(lo, hi, spheres[k]);
    if (o == Overlap::kNone) return true;
    if (o == Overlap::kPartial) {
      crossing.push_back(spheres[k]);
      index.push_back(k);
    }
  }
  if (crossing.empty()) {
    const nurbs::GaussRule g = nurbs::gauss_legendre(points);
    for (size_t k = 0; k < g.points.size(); ++k)
      for (size_t j = 0; j < g.points.size(); ++j)
        for (size_t i = 0; i < g.points.size(); ++i) {
          const Eigen::Vector3d t(g.points[i], g.points[j], g.points[k]);
          out.points.push_back(0.5 * (lo + hi) + 0.5 * (hi - lo).cwiseProduct(t));
          out.weights.push_back(0.125 * (hi - lo).prod() * g.weights[i] * g.weights[j] *
                                g.weights[k]);
        }
    return false;
  }
  cut_box(lo, hi, crossing, spheres, index, first_face, points, cut_points, depth, warning, out);
  return true;
}

void sphere_box_face(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, int d, double t,
                     const std::vector<ImplicitSphere>& spheres, int points, std::string& warning,
                     std::vector<Eigen::Vector3d>& out_points, std::vector<double>& out_weights) {
  std::vector<LineCircle> circles;
  for (const auto& s : spheres) {
    const LineCircle c = plane_circle(s, d, t, s.part_inside, false);
    if (c.radius == 0) {
      if (s.part_inside) return;  // the plane misses a sphere the part lies in
      continue;
    }
    circles.push_back(c);
  }
  const PlaneRule rule = cut_rectangle_rule({lo, hi}, circles, points, warning);
  for (size_t q = 0; q < rule.points.size(); ++q) {
    out_points.push_back(compose(d, t, rule.points[q]));
    out_weights.push_back(rule.weights[q]);
  }
}

}  // namespace isospring::geometry::detail
