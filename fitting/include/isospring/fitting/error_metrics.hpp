#pragma once
// %e_rms and %e_max [NC10, S15 4.20-4.21] on control points and on the physical model.
#include <Eigen/Core>
#include <array>
#include <vector>

#include "isospring/nurbs/patch.hpp"

namespace isospring::fitting {

struct ErrorMetrics {
  double percent_e_rms = 0.0;  // 100 sqrt(1/n sum |u_ref - u|^2) / o_max
  double percent_e_max = 0.0;  // 100 max |u_ref - u| / o_max
  double o_max = 0.0;          // max |u_ref|
  int points = 0;
};

/// Over paired points. Throws nurbs::InputError when the sizes differ or o_max is zero.
ErrorMetrics error_metrics(const std::vector<Eigen::Vector3d>& reference,
                           const std::vector<Eigen::Vector3d>& model);

/// Over the physical model: both displacement fields sum_a R_a(xi) u_a evaluated at `samples`
/// equally spaced parameters per direction of every patch (displaced control nets, same basis).
/// `reference` and `model` are [patch][control point].
ErrorMetrics field_error_metrics(const std::vector<nurbs::Patch>& patches,
                                 const std::vector<std::vector<Eigen::Vector3d>>& reference,
                                 const std::vector<std::vector<Eigen::Vector3d>>& model,
                                 int samples = 11);

/// Over the physical surface: like field_error_metrics, but a volume patch is sampled on its
/// boundary faces only (`samples` per direction, each point once: samples^3 - (samples - 2)^3
/// per patch when every face is outer), which is what a user sees and what markers measure; surface
/// patches (membranes) are sampled over their whole domain. `inner` ([patch][2 * dir + end], as
/// analysis::inner_sides gives it; empty: none) names faces that are not on the surface
/// (interfaces between patches, seams, collapsed axes), which are left out; their edges stay
/// where they border an outer face.
ErrorMetrics surface_error_metrics(const std::vector<nurbs::Patch>& patches,
                                   const std::vector<std::vector<Eigen::Vector3d>>& reference,
                                   const std::vector<std::vector<Eigen::Vector3d>>& model,
                                   int samples = 11,
                                   const std::vector<std::array<bool, 6>>& inner = {});

}  // namespace isospring::fitting
