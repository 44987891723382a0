#pragma once
// Matrices the identification needs beyond analysis::assemble_stiffness: the stiffness split into
// its Lame parts with a spatial weight (stiffness gradients, exact parameter derivatives) and
// boundary spring matrices on a side (compliant supports).
#include <Eigen/Sparse>
#include <functional>

#include "isospring/analysis/dof_map.hpp"
#include "isospring/analysis/lame_stiffness.hpp"
#include "isospring/analysis/problem.hpp"

namespace isospring::fitting {

/// The stiffness split into its Lame parts with the weight w(x) (1 when empty):
/// analysis::assemble_lame_stiffness for one weight.
using LameMatrices = analysis::LameStiffness;
LameMatrices assemble_lame_stiffness(const analysis::Problem& problem, const analysis::DofMap& dofs,
                                     const analysis::SpatialWeight& weight = {});

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
