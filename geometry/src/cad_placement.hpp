#pragma once
// Checks of a rigid placement's rotation, shared by transform_solid and the immersion's frame.
#include <Eigen/Core>
#include <string>

namespace isospring::geometry::detail {

/// Throws nurbs::InputError naming `what` and the fix unless `rotation` is orthonormal to 1e-12
/// (|R^T R - I|, max norm) with det = +1 (not a reflection).
void check_rotation(const Eigen::Matrix3d& rotation, const std::string& what);

/// Whether `rotation` is the identity exactly (then no placement is needed).
bool is_identity(const Eigen::Matrix3d& rotation);

}  // namespace isospring::geometry::detail
