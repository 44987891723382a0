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

Inversion invert_point(const Patch& patch, const Eigen::Vector3d& x, std::optional<Param> start,
                       double tolerance) {
  const int d = patch.param_dim();
  Param u = clamp_to_box(patch, start ? *start : best_sample(patch, x));
  Objective current = objective(patch, u, x);
  const auto [lo, hi] = patch.control_bounds();
  const double scale = std::max((hi - lo).norm(), 1e-300);
  Inversion result;
  for (int iteration = 1; iteration <= 100; ++iteration) {
    result.iterations = iteration;
    // Newton step on the free parameters (those not pinned at a bound with the gradient pushing
    // outwards): a projected Newton method for the box-constrained problem.
    Eigen::Vector3d step = Eigen::Vector3d::Zero();
    std::array<bool, 3> free{false, false, false};
    for (int a = 0; a < d; ++a) {
      const bool at_min = u[a] <= patch.param_min(a) && current.gradient(a) > 0;
      const bool at_max = u[a] >= patch.param_max(a) && current.gradient(a) < 0;
      free[a] = !(at_min || at_max);
    }
    Eigen::Matrix3d h = current.hessian;
    Eigen::Vector3d g = current.gradient;
    for (int a = 0; a < 3; ++a)
      if (a >= d || !free[a]) {
        h.row(a).setZero();
        h.col(a).setZero();
        h(a, a) = 1.0;
        g(a) = 0.0;
      }
    Eigen::LDLT<Eigen::Matrix3d> ldlt(h);
    if (ldlt.info() == Eigen::Success && ldlt.isPositive()) {
      step = -ldlt.solve(g);
    } else {
      // Indefinite Hessian (far from the minimum on a curved patch): steepest descent scaled by
      // the Gauss-Newton curvature.
      step = -g / std::max(h.diagonal().cwiseAbs().maxCoeff(), 1e-300);
    }
    // Backtracking keeps every iterate inside the box and decreasing.
    double factor = 1.0;
    Param trial = u;
    Objective next = current;
    bool improved = false;
    for (int halving = 0; halving < 30; ++halving) {
      for (int a = 0; a < d; ++a) trial[a] = u[a] + factor * step(a);
      trial = clamp_to_box(patch, trial);
      next = objective(patch, trial, x);
      if (next.value <= current.value) {
        improved = true;
        break;
      }
      factor *= 0.5;
    }
    double moved = 0.0;
    for (int a = 0; a < d; ++a)
      moved =
          std::max(moved, std::abs(trial[a] - u[a]) / (patch.param_max(a) - patch.param_min(a)));
    if (improved) {
      u = trial;
      current = next;
    }
    // Converged: zero distance, or the projected gradient (cosine between the residual and the
    // tangents) vanishes, or the parameter no longer moves.
    const double distance = std::sqrt(current.value);
    double projected = 0.0;
    for (int a = 0; a < d; ++a)
      if (free[a]) projected = std::max(projected, std::abs(current.gradient(a)));
    if (distance <= tolerance * scale || projected <= tolerance * scale * scale ||
        moved <= tolerance || !improved) {
      result.converged = true;
      break;
    }
  }
  result.param = u;
  result.point = current.point;
  result.distance = (current.point - x).norm();
  return result;
}

}  // namespace isospring::nurbs
