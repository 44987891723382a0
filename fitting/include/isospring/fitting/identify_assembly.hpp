#pragma once
// Matrices the identification needs beyond analysis::assemble_stiffness: the stiffness split into
// its Lame parts with a spatial weight (stiffness gradients, exact parameter derivatives) and
// boundary spring matrices on a side (compliant supports).
#include <Eigen/Sparse>
#include <functional>

#include "isospring/analysis/dof_map.hpp"
#include "isospring/analysis/problem.hpp"

namespace isospring::fitting {

/// K = lambda * lambda_part + mu * mu_part for a homogeneous material (lambda is the plane-stress
/// lambda* in plane stress, as analysis::lame_parameters). Both parts are full symmetric matrices
/// (not only the upper triangle) over the DOFs of `dofs`:
///   lambda_part[(a,i),(b,j)] = int w dR_a/dx_i dR_b/dx_j
///   mu_part[(a,i),(b,j)]     = int w (delta_ij grad R_a . grad R_b + dR_a/dx_j dR_b/dx_i)
/// with the weight w(x) (1 when empty), times the thickness in 2D.
struct LameMatrices {
  Eigen::SparseMatrix<double> lambda_part;
  Eigen::SparseMatrix<double> mu_part;
};
LameMatrices assemble_lame_stiffness(
    const analysis::Problem& problem, const analysis::DofMap& dofs,
    const std::function<double(const Eigen::Vector3d&)>& weight = {});

/// Boundary springs on a side (full symmetric): normal = int R_a R_b n n^T and
/// tangential = int R_a R_b (I - n n^T) over the side (times the thickness in 2D), so that
/// k_n * normal + k_t * tangential is the stiffness of springs per area k_n, k_t [Pa/m].
struct SideSpringMatrices {
  Eigen::SparseMatrix<double> normal;
  Eigen::SparseMatrix<double> tangential;
};
SideSpringMatrices assemble_side_springs(const analysis::Problem& problem,
                                         const analysis::DofMap& dofs, const analysis::Side& side);

}  // namespace isospring::fitting
