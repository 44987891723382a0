// Error metrics on points and on sampled displacement fields.
#include "isospring/fitting/error_metrics.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "isospring/nurbs/error.hpp"

namespace isospring::fitting {

ErrorMetrics error_metrics(const std::vector<Eigen::Vector3d>& reference,
                           const std::vector<Eigen::Vector3d>& model) {
  if (reference.size() != model.size() || reference.empty())
    throw nurbs::InputError("error metrics: reference and model have different point counts");
  ErrorMetrics m;
  m.points = static_cast<int>(reference.size());
  double sum = 0.0, worst = 0.0;
  for (size_t a = 0; a < reference.size(); ++a) {
    m.o_max = std::max(m.o_max, reference[a].norm());
    const double e = (reference[a] - model[a]).norm();
    sum += e * e;
    worst = std::max(worst, e);
  }
  if (!(m.o_max > 0.0))
    throw nurbs::InputError("error metrics: the reference displacement is zero everywhere");
  m.percent_e_rms = 100.0 * std::sqrt(sum / m.points) / m.o_max;
  m.percent_e_max = 100.0 * worst / m.o_max;
  return m;
}

namespace {

// Both displacement fields sum_a R_a(xi) u_a at the grid points (i, j, k) of `samples` equally
// spaced parameters per direction of every patch p that keep(p, patch, at) accepts.
template <typename Keep>
ErrorMetrics sampled_error_metrics(const std::vector<nurbs::Patch>& patches,
                                   const std::vector<std::vector<Eigen::Vector3d>>& reference,
                                   const std::vector<std::vector<Eigen::Vector3d>>& model,
                                   int samples, Keep keep) {
  std::vector<Eigen::Vector3d> ref_points, model_points;
  for (size_t p = 0; p < patches.size(); ++p) {
    const nurbs::Patch& patch = patches[p];
    const int dims = patch.param_dim();
    std::array<int, 3> count{1, 1, 1};
    for (int d = 0; d < dims; ++d) count[d] = samples;
    for (int k = 0; k < count[2]; ++k)
      for (int j = 0; j < count[1]; ++j)
        for (int i = 0; i < count[0]; ++i) {
          const std::array<int, 3> at{i, j, k};
          if (!keep(p, patch, at)) continue;
          nurbs::Param u{0.0, 0.0, 0.0};
          for (int d = 0; d < dims; ++d)
            u[d] = patch.param_min(d) +
                   (patch.param_max(d) - patch.param_min(d)) * at[d] / std::max(1, samples - 1);
          const nurbs::RationalBasis basis = patch.basis(u, 0);
          Eigen::Vector3d ur = Eigen::Vector3d::Zero(), um = Eigen::Vector3d::Zero();
          for (size_t a = 0; a < basis.indices.size(); ++a) {
            ur += basis.values[static_cast<Eigen::Index>(a)] * reference[p][basis.indices[a]];
            um += basis.values[static_cast<Eigen::Index>(a)] * model[p][basis.indices[a]];
          }
          ref_points.push_back(ur);
          model_points.push_back(um);
        }
  }
  return error_metrics(ref_points, model_points);
}

}  // namespace

ErrorMetrics field_error_metrics(const std::vector<nurbs::Patch>& patches,
                                 const std::vector<std::vector<Eigen::Vector3d>>& reference,
                                 const std::vector<std::vector<Eigen::Vector3d>>& model,
                                 int samples) {
  return sampled_error_metrics(
      patches, reference, model, samples,
      [](size_t, const nurbs::Patch&, const std::array<int, 3>&) { return true; });
}

ErrorMetrics surface_error_metrics(const std::vector<nurbs::Patch>& patches,
                                   const std::vector<std::vector<Eigen::Vector3d>>& reference,
                                   const std::vector<std::vector<Eigen::Vector3d>>& model,
                                   int samples, const std::vector<std::array<bool, 6>>& inner) {
  if (!inner.empty() && inner.size() != patches.size())
    throw nurbs::InputError("surface error metrics: inner faces for " +
                            std::to_string(inner.size()) + " patches, the model has " +
                            std::to_string(patches.size()));
  const int last = std::max(1, samples - 1);
  return sampled_error_metrics(
      patches, reference, model, samples,
      [&, last](size_t p, const nurbs::Patch& patch, const std::array<int, 3>& at) {
        if (patch.param_dim() < 3) return true;  // a membrane is its own surface
        for (int d = 0; d < 3; ++d)
          for (int end = 0; end < 2; ++end)
            if (at[d] == (end == 0 ? 0 : last) &&
                (inner.empty() || !inner[p][static_cast<size_t>(2 * d + end)]))
              return true;
        return false;
      });
}

}  // namespace isospring::fitting
