#include "isospring/nurbs/point_inversion.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

namespace isospring::nurbs {
namespace {

/// Squared distance and its gradient/Hessian in parameter space (Gauss-Newton plus curvature).
struct Objective {
  double value;
  Eigen::Vector3d gradient;
  Eigen::Matrix3d hessian;
  Eigen::Vector3d point;
};

Objective objective(const Patch& patch, const Param& u, const Eigen::Vector3d& x) {
  const int d = patch.param_dim();
  const PatchDerivatives der = patch.derivatives(u, 2);
  const Eigen::Vector3d r = der.point - x;
  Objective out{r.squaredNorm(), Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity(), der.point};
  for (int a = 0; a < d; ++a) {
    out.gradient(a) = 2.0 * der.first.col(a).dot(r);
    for (int b = 0; b < d; ++b)
      out.hessian(a, b) =
          2.0 * (der.first.col(a).dot(der.first.col(b)) + der.second[a].col(b).dot(r));
  }
  return out;
}

Param clamp_to_box(const Patch& patch, Param u) {
  for (int a = 0; a < patch.param_dim(); ++a)
    u[a] = std::clamp(u[a], patch.param_min(a), patch.param_max(a));
  return u;
}

Param best_sample(const Patch& patch, const Eigen::Vector3d& x) {
  // Several samples per element and direction: enough to land in the basin of the global
  // minimum for the moderately curved patches analysis uses.
  const int d = patch.param_dim();
  std::array<std::vector<double>, 3> samples;
  for (int a = 0; a < 3; ++a) {
    if (a >= d) {
      samples[a] = {0.0};
      continue;
    }
    const std::vector<double> breaks = patch.knots(a).unique();
    const int per_element = std::max(3, patch.degree(a) + 2);
    for (size_t e = 0; e + 1 < breaks.size(); ++e)
      for (int s = 0; s < per_element; ++s)
        samples[a].push_back(breaks[e] + (breaks[e + 1] - breaks[e]) * s / per_element);
    samples[a].push_back(breaks.back());
  }
  Param best{0, 0, 0};
  double best_distance = std::numeric_limits<double>::infinity();
  for (double w : samples[2])
    for (double v : samples[1])
      for (double u : samples[0]) {
        const Param p{u, v, w};
        const double distance = (patch.point(p) - x).squaredNorm();
        if (distance < best_distance) {
          best_distance = distance;
          best = p;
        }
      }
  return best;
}

}  // namespace

namespace {

/// Largest cosine between the residual X(u) - x and the tangents of the free directions: zero at
/// a constrained stationary point (The NURBS Book eq. 6.4, zero-cosine criterion). Unlike the
/// squared distance, it resolves the optimum to round-off rather than to sqrt(epsilon).
double stationarity(const Patch& patch, const Param& u, const Eigen::Vector3d& residual,
                    const std::array<bool, 3>& free) {
  const double r = residual.norm();
  if (r == 0.0) return 0.0;
  const PatchDerivatives der = patch.derivatives(u, 1);
  double worst = 0.0;
  for (int a = 0; a < patch.param_dim(); ++a) {
    if (!free[static_cast<size_t>(a)]) continue;
    const double t = der.first.col(a).norm();
    if (t > 0.0) worst = std::max(worst, std::abs(der.first.col(a).dot(residual)) / (t * r));
  }
  return worst;
}

}  // namespace

Inversion invert_point(const Patch& patch, const Eigen::Vector3d& x, std::optional<Param> start,
                       double tolerance) {
  const int d = patch.param_dim();
  Param u = clamp_to_box(patch, start ? *start : best_sample(patch, x));
  const auto [lo, hi] = patch.control_bounds();
  const double scale = std::max((hi - lo).norm(), 1e-300);
  // A parameter within round-off of a bound is on it (a start like v = 1 - 1e-16 must be pinned).
  auto snap = [&](Param v) {
    for (int a = 0; a < d; ++a) {
      const double eps =
          64 * std::numeric_limits<double>::epsilon() * (patch.param_max(a) - patch.param_min(a));
      if (v[a] - patch.param_min(a) <= eps) v[a] = patch.param_min(a);
      if (patch.param_max(a) - v[a] <= eps) v[a] = patch.param_max(a);
    }
    return v;
  };
  u = snap(u);
  Objective current = objective(patch, u, x);
  Inversion result;
  for (int iteration = 1; iteration <= 100; ++iteration) {
    result.iterations = iteration;
    // Projected Newton for the box-constrained problem: directions pinned at a bound with the
    // gradient pushing outwards are held; the others take a Newton step.
    std::array<bool, 3> free{false, false, false};
    for (int a = 0; a < d; ++a) {
      const bool at_min = u[a] <= patch.param_min(a) && current.gradient(a) > 0;
      const bool at_max = u[a] >= patch.param_max(a) && current.gradient(a) < 0;
      free[static_cast<size_t>(a)] = !(at_min || at_max);
    }
    const double distance = std::sqrt(current.value);
    if (distance <= tolerance * scale ||
        stationarity(patch, u, current.point - x, free) <= tolerance) {
      result.converged = true;
      break;
    }
    Eigen::Matrix3d h = current.hessian;
    Eigen::Vector3d g = current.gradient;
    for (int a = 0; a < 3; ++a)
      if (a >= d || !free[static_cast<size_t>(a)]) {
        h.row(a).setZero();
        h.col(a).setZero();
        h(a, a) = 1.0;
        g(a) = 0.0;
      }
    Eigen::Vector3d step;
    Eigen::LDLT<Eigen::Matrix3d> ldlt(h);
    if (ldlt.info() == Eigen::Success && ldlt.isPositive()) {
      step = -ldlt.solve(g);
    } else {
      // Indefinite Hessian (far from the minimum on a curved patch): steepest descent scaled by
      // the curvature.
      step = -g / std::max(h.diagonal().cwiseAbs().maxCoeff(), 1e-300);
    }
    // Backtracking: accept a step that lowers the distance or, once the distance no longer
    // resolves progress (near the optimum), the gradient.
    double factor = 1.0;
    bool improved = false;
    Param trial = u;
    Objective next = current;
    for (int halving = 0; halving < 40 && !improved; ++halving, factor *= 0.5) {
      for (int a = 0; a < d; ++a) trial[a] = u[a] + factor * step(a);
      trial = snap(clamp_to_box(patch, trial));
      next = objective(patch, trial, x);
      // Only the free components: a pinned direction's (large) gradient must not mask progress.
      Eigen::Vector3d g_next = next.gradient;
      for (int a = 0; a < 3; ++a)
        if (a >= d || !free[static_cast<size_t>(a)]) g_next(a) = 0.0;
      improved = next.value < current.value ||
                 (next.value <= current.value * (1 + 1e-12) && g_next.norm() < g.norm());
    }
    if (!improved) {
      // No step helps at the resolution of double precision: this is the optimum.
      result.converged = true;
      break;
    }
    u = trial;
    current = next;
  }
  result.param = u;
  result.point = current.point;
  result.distance = (current.point - x).norm();
  return result;
}

}  // namespace isospring::nurbs
