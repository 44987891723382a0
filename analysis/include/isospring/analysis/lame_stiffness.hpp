#pragma once
// The linear-elastic stiffness split by Lame parameter, with spatial weights: what a model of a
// graded or unknown homogeneous material needs (isospring::fitting's stiffness parameters).
#include <Eigen/Sparse>
#include <functional>
#include <vector>

#include "isospring/analysis/dof_map.hpp"
#include "isospring/analysis/problem.hpp"

namespace isospring::analysis {

/// K = lambda * lambda_part + mu * mu_part for a homogeneous material (lambda is the plane-stress
/// lambda* in plane stress, as lame_parameters). Both parts are full symmetric matrices (not only
/// the upper triangle) over the DOFs of `dofs`:
///   lambda_part[(a,i),(b,j)] = int w dR_a/dx_i dR_b/dx_j
///   mu_part[(a,i),(b,j)]     = int w (delta_ij grad R_a . grad R_b + dR_a/dx_j dR_b/dx_i)
/// with a weight w(x), times the thickness in 2D. Quadrature as assemble_stiffness.
/// Under Volumetric::kBbar (solids and plane strain) the parts are B-bar's, still linear in the
/// Lame parameters: lambda_part = t C^T G_w C (the projected dilatation's, G_w the projection
/// space's Gram weighted by w) and mu_part = the displacement mu part - 2/3 (the displacement
/// lambda part - lambda_part); for w = 1, lambda lambda_part + mu mu_part is
/// assemble_stiffness's B-bar matrix (derivation in analysis/src/bbar_lame_parts.hpp).
struct LameStiffness {
  Eigen::SparseMatrix<double> lambda_part;
  Eigen::SparseMatrix<double> mu_part;
};

/// A weight of the integrand at a physical point.
using SpatialWeight = std::function<double(const Eigen::Vector3d&)>;

/// One LameStiffness per weight (an empty function is w = 1), from one pass over the elements:
/// the basis gradients are evaluated once for all weights. Elements run colour by colour on
/// `threads` threads (0: OpenMP's default). Throws nurbs::InputError on a non-positive Jacobian.
std::vector<LameStiffness> assemble_lame_stiffness(const Problem& problem, const DofMap& dofs,
                                                   const std::vector<SpatialWeight>& weights,
                                                   int threads = 0);

}  // namespace isospring::analysis
