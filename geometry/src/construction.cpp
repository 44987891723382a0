#include "isospring/geometry/construction.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "isospring/nurbs/error.hpp"
#include "isospring/nurbs/quadrature.hpp"
#include "isospring/nurbs/refine.hpp"

namespace isospring::geometry {

using nurbs::KnotVector;
using nurbs::Patch;

nurbs::Patch circular_arc(const Eigen::Vector3d& center, double radius, double start,
                          double sweep) {
  if (!(radius > 0.0) || !(std::abs(sweep) > 0.0) || std::abs(sweep) > 2.0 * M_PI + 1e-12)
    throw nurbs::InputError(
        "circular arc: the radius must be positive and the sweep in "
        "(0, 2 pi] radians in magnitude");
  // Tolerance so that an exact quarter (pi/2 computed in floating point) stays one segment.
  const int segments =
      std::max(1, static_cast<int>(std::ceil(std::abs(sweep) / (M_PI / 2) - 1e-9)));
  const double step = sweep / segments;
  const double half_weight = std::cos(step / 2.0);  // weight of each middle control point
  std::vector<double> knots{0.0, 0.0, 0.0};
  for (int s = 1; s < segments; ++s) {
    knots.push_back(static_cast<double>(s) / segments);
    knots.push_back(static_cast<double>(s) / segments);
  }
  knots.insert(knots.end(), {1.0, 1.0, 1.0});
  std::vector<Eigen::Vector3d> points;
  std::vector<double> weights;
  auto on_circle = [&](double angle, double r) {
    return Eigen::Vector3d(center.x() + r * std::cos(angle), center.y() + r * std::sin(angle),
                           center.z());
  };
  points.push_back(on_circle(start, radius));
  weights.push_back(1.0);
  for (int s = 0; s < segments; ++s) {
    const double a0 = start + s * step;
    // The middle control point is the intersection of the end tangents.
    points.push_back(on_circle(a0 + step / 2.0, radius / half_weight));
    weights.push_back(half_weight);
    points.push_back(on_circle(a0 + step, radius));
    weights.push_back(1.0);
  }
  return Patch({KnotVector(2, knots)}, points, weights);
}

nurbs::Patch ruled(const nurbs::Patch& from, const nurbs::Patch& to) {
  if (from.param_dim() != to.param_dim() || from.param_dim() >= 3 ||
      from.num_points() != to.num_points())
    throw std::invalid_argument("ruled: both sides need the same knots and at most 2 directions");
  for (int d = 0; d < from.param_dim(); ++d)
    if (from.knots(d).values() != to.knots(d).values() || from.degree(d) != to.degree(d))
      throw std::invalid_argument("ruled: both sides need the same knot vectors");
  std::vector<KnotVector> knots = from.all_knots();
  knots.push_back(KnotVector(1, {0.0, 0.0, 1.0, 1.0}));
  std::vector<Eigen::Vector3d> points = from.control_points();
  points.insert(points.end(), to.control_points().begin(), to.control_points().end());
  std::vector<double> weights = from.weights();
  weights.insert(weights.end(), to.weights().begin(), to.weights().end());
  return Patch(knots, points, weights);
}

nurbs::Patch extrude(const nurbs::Patch& profile, const Eigen::Vector3d& offset) {
  return ruled(profile, transformed(profile, Eigen::Matrix3d::Identity(), offset));
}

nurbs::Patch revolve_about_z(const nurbs::Patch& profile, double sweep) {
  if (profile.param_dim() >= 3)
    throw std::invalid_argument("revolve_about_z: the profile must be a curve or a surface");
  // Unit-circle arc from angle 0: multiplying a profile point (x + i y) by an arc control point
  // (as a complex number) rotates it and scales it by the arc's radius, which maps the tangent
  // intersections exactly (a similarity transform commutes with the rational construction).
  const Patch arc = circular_arc(Eigen::Vector3d::Zero(), 1.0, 0.0, sweep);
  std::vector<KnotVector> knots{arc.knots(0)};
  for (const auto& k : profile.all_knots()) knots.push_back(k);
  std::vector<Eigen::Vector3d> points;
  std::vector<double> weights;
  for (int j = 0; j < profile.num_points(); ++j) {
    const Eigen::Vector3d& p = profile.control_point(j);
    for (int i = 0; i < arc.num_points(); ++i) {
      const Eigen::Vector3d& q = arc.control_point(i);
      points.emplace_back(q.x() * p.x() - q.y() * p.y(), q.x() * p.y() + q.y() * p.x(), p.z());
      weights.push_back(arc.weight(i) * profile.weight(j));
    }
  }
  return Patch(knots, points, weights);
}

nurbs::Patch reverse_direction(const nurbs::Patch& patch, int dir) {
  std::vector<KnotVector> knots = patch.all_knots();
  const KnotVector& old = patch.knots(dir);
  std::vector<double> values(old.values().rbegin(), old.values().rend());
  for (double& t : values) t = old.first() + old.last() - t;
  knots[static_cast<size_t>(dir)] = KnotVector(old.degree(), values);
  std::vector<Eigen::Vector3d> points(patch.control_points().size());
  std::vector<double> weights(points.size());
  const int n = patch.num_points(dir);
  for (int a = 0; a < patch.num_points(); ++a) {
    auto ijk = patch.net_position(a);
    ijk[static_cast<size_t>(dir)] = n - 1 - ijk[static_cast<size_t>(dir)];
    const auto b = static_cast<size_t>(patch.index(ijk[0], ijk[1], ijk[2]));
    points[b] = patch.control_point(a);
    weights[b] = patch.weight(a);
  }
  return Patch(knots, points, weights);
}

std::pair<nurbs::Patch, nurbs::Patch> split_patch(const nurbs::Patch& patch, int dir, double u) {
  const KnotVector& kv = patch.knots(dir);
  if (!(u > kv.first() && u < kv.last()))
    throw std::invalid_argument("split_patch: the parameter must be inside the range");
  const int p = kv.degree();
  const int existing = kv.multiplicity(u);
  const Patch full = existing < p ? nurbs::insert_knot(patch, dir, u, p - existing) : patch;
  const KnotVector& fk = full.knots(dir);
  // Knot vector of each half: clamp the full vector at u (which now has multiplicity p).
  std::vector<double> left, right;
  for (double t : fk.values()) {
    if (t <= u) left.push_back(t);
    if (t >= u) right.push_back(t);
  }
  left.push_back(u);
  right.insert(right.begin(), u);
  const int n_left = static_cast<int>(left.size()) - p - 1;
  auto half = [&](const std::vector<double>& values, int first_index) {
    std::vector<KnotVector> knots = full.all_knots();
    knots[static_cast<size_t>(dir)] = KnotVector(p, values);
    const int n = static_cast<int>(values.size()) - p - 1;
    std::vector<Eigen::Vector3d> points;
    std::vector<double> weights;
    for (int a = 0; a < full.num_points(); ++a) {
      const int i = full.net_position(a)[static_cast<size_t>(dir)];
      if (i < first_index || i >= first_index + n) continue;
      points.push_back(full.control_point(a));
      weights.push_back(full.weight(a));
    }
    return Patch(knots, points, weights);
  };
  return {half(left, 0), half(right, n_left - 1)};
}

nurbs::Patch transformed(const nurbs::Patch& patch, const Eigen::Matrix3d& A,
                         const Eigen::Vector3d& b) {
  std::vector<Eigen::Vector3d> points;
  points.reserve(patch.control_points().size());
  for (const auto& x : patch.control_points()) points.push_back(A * x + b);
  return Patch(patch.all_knots(), points, patch.weights());
}

double jacobian_determinant(const nurbs::Patch& patch, const nurbs::Param& u) {
  const nurbs::PatchDerivatives d = patch.derivatives(u, 1);
  switch (patch.param_dim()) {
    case 1:
      return d.first.col(0).norm();
    case 2: {
      const Eigen::Vector3d n = d.first.col(0).cross(d.first.col(1));
      return patch.physical_dim() == 2 ? n.z() : n.norm();
    }
    default:
      return d.first.determinant();
  }
}

JacobianRange jacobian_range(const nurbs::Patch& patch, int samples) {
  const nurbs::GaussRule rule = nurbs::gauss_legendre(samples);
  JacobianRange range{std::numeric_limits<double>::infinity(),
                      -std::numeric_limits<double>::infinity()};
  const int dim = patch.param_dim();
  std::array<std::vector<double>, 3> params;
  for (int d = 0; d < 3; ++d) {
    if (d >= dim) {
      params[static_cast<size_t>(d)] = {0.0};
      continue;
    }
    const std::vector<double> breaks = patch.knots(d).unique();
    for (size_t e = 0; e + 1 < breaks.size(); ++e)
      for (double g : rule.points)
        params[static_cast<size_t>(d)].push_back(breaks[e] +
                                                 (g + 1.0) / 2.0 * (breaks[e + 1] - breaks[e]));
  }
  for (double w : params[2])
    for (double v : params[1])
      for (double u : params[0]) {
        const double det = jacobian_determinant(patch, {u, v, w});
        range.min = std::min(range.min, det);
        range.max = std::max(range.max, det);
      }
  return range;
}

nurbs::Patch with_positive_jacobian(const nurbs::Patch& patch) {
  const JacobianRange range = jacobian_range(patch);
  if (range.min > 0.0) return patch;
  if (range.max < 0.0) return reverse_direction(patch, 0);
  throw std::runtime_error("patch parametrisation folds: the Jacobian changes sign (min " +
                           std::to_string(range.min) + ", max " + std::to_string(range.max) + ")");
}

}  // namespace isospring::geometry

namespace isospring::geometry {

nurbs::Patch swap_directions(const nurbs::Patch& patch, int a, int b) {
  std::vector<KnotVector> knots = patch.all_knots();
  std::swap(knots[static_cast<size_t>(a)], knots[static_cast<size_t>(b)]);
  std::array<int, 3> n{patch.num_points(0), patch.num_points(1), patch.num_points(2)};
  std::swap(n[static_cast<size_t>(a)], n[static_cast<size_t>(b)]);
  std::vector<Eigen::Vector3d> points(patch.control_points().size());
  std::vector<double> weights(points.size());
  for (int i = 0; i < patch.num_points(); ++i) {
    auto ijk = patch.net_position(i);
    std::swap(ijk[static_cast<size_t>(a)], ijk[static_cast<size_t>(b)]);
    const auto j = static_cast<size_t>(ijk[0] + n[0] * (ijk[1] + n[1] * ijk[2]));
    points[j] = patch.control_point(i);
    weights[j] = patch.weight(i);
  }
  return Patch(knots, points, weights);
}

}  // namespace isospring::geometry
