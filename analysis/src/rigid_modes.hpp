#pragma once
// Rigid-body motions restricted to what the supports hold: shared by the body-fitted check
// (rigid_body_check.cpp, supported control points) and the immersed one (supported faces).
#include <Eigen/Core>
#include <string>

namespace isospring::analysis::detail {

/// Component c of the 3 (2D) or 6 (3D) rigid motions at x (centred and scaled by the part's
/// size, so every entry is O(1)): translations first, then rotations about x, y, z (2D: about z).
Eigen::VectorXd rigid_mode_row(const Eigen::Vector3d& x, int c, int dim);

/// `gram` is the Gram matrix of the rigid motions over what the supports hold. When it is
/// singular, throws nurbs::InputError "the supports leave free: <motions> (rigid-body motion of
/// <owner>); add supports (<remedy>) that block this motion".
void throw_if_rigid_modes_free(const Eigen::MatrixXd& gram, int dim, const std::string& owner,
                               const std::string& remedy);

}  // namespace isospring::analysis::detail
