#pragma once
// The normal springs of a compliant support split by the shape of the normal displacement: its
// uniform part (the support's axial compliance), its linearly varying part (rocking about the
// side's in-plane axes) and the rest. A thin bonded layer of a nearly incompressible material
// resists the uniform part far more than rocking (its material must flow out to the free edges
// in the first case, only from one half of the side to the other in the second), so a support
// model with one normal stiffness cannot be both; with the split, each part gets its own.
#include <Eigen/Sparse>

#include "isospring/analysis/dof_map.hpp"
#include "isospring/analysis/problem.hpp"

namespace isospring::fitting {

/// normal = axial + rocking + rest, each symmetric positive semi-definite:
/// - axial = N t t^T N / (t^T N t), t the unit translation along the side's mean normal (the
///   principal direction of the springs' 3 x 3 Gram matrix of translations): for a flat side,
///   u^T axial u = A * (mean normal displacement)^2;
/// - rocking = the same projection onto the rigid rotations about the side's in-plane axes
///   (through the centroid of its control points), made N-orthogonal to t: for a flat side,
///   u^T rocking u = theta^T I theta for the tilt theta of the normal displacement's linear fit
///   (I: the side's second moments of area about its centroid);
/// - rest = normal - axial - rocking (the normal displacement's deviation from a plane).
/// In 2D (plane stress or strain) the one rotation is about the out-of-plane axis.
/// `normal` is assemble_side_springs(...).normal of `side` (full symmetric).
struct NormalSpringSplit {
  Eigen::SparseMatrix<double> axial, rocking, rest;
};
NormalSpringSplit split_normal_springs(const analysis::Problem& problem,
                                       const analysis::DofMap& dofs, const analysis::Side& side,
                                       const Eigen::SparseMatrix<double>& normal);

}  // namespace isospring::fitting
