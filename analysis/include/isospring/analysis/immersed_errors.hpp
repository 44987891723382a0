#pragma once
// Error norms of an immersed solution against a closed form, over the part only: the relative L2
// norm of the displacement and the energy norm sqrt(int (sigma - sigma_h) : (eps - eps_h)).
//
// Inside cells are integrated with their own tensor Gauss rule of `inside_points` per direction
// (default degree + 3), not with the solver's degree + 1 points: the solver's rule sits on the
// points where the discrete stress superconverges and would understate the energy error. Cut
// cells keep the domain's quadrature (Gauss-exact along lines, degree + 2 points or more), the
// only one that follows the exact boundary.
#include <Eigen/Core>
#include <functional>

#include "isospring/analysis/immersed.hpp"
#include "isospring/analysis/post_processing.hpp"

namespace isospring::analysis {

ErrorNorms immersed_error_norms(
    const geometry::ImmersedDomain& domain, const ImmersedResult& result,
    const ImmersedOptions& options,
    const std::function<Eigen::Vector3d(const Eigen::Vector3d&)>& exact_u,
    const std::function<Eigen::Matrix3d(const Eigen::Vector3d&)>& exact_stress,
    int inside_points = 0);

}  // namespace isospring::analysis
