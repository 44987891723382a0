#pragma once
// The stiffnesses a displacement fit reports, from its log-stiffness parameters: shared by the
// linear and the nonlinear (large-deformation) fit, which optimise the same parameters.
#include <cmath>
#include <vector>

#include "isospring/fitting/displacement_fit.hpp"
#include "isospring/fitting/stiffness_groups.hpp"

namespace isospring::fitting::detail {

/// Fills result.group_stiffness = exp(theta), groups_at_lower_bound (theta within 1e-9 of
/// log_floor in log: both solvers project onto the bound exactly) and the per-spring and
/// per-volume-term values the grouping maps them to.
inline void set_fitted_stiffnesses(const std::vector<double>& theta, double log_floor,
                                   const Grouping& grouping, DisplacementFitResult& result) {
  for (size_t g = 0; g < theta.size(); ++g) {
    result.group_stiffness.push_back(std::exp(theta[g]));
    if (theta[g] <= log_floor + 1e-9) ++result.groups_at_lower_bound;
  }
  for (int g : grouping.group_of_spring)
    result.spring_stiffness.push_back(result.group_stiffness[g]);
  for (int g : grouping.group_of_volume) result.volume_modulus.push_back(result.group_stiffness[g]);
}

}  // namespace isospring::fitting::detail
