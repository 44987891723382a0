#pragma once
// The Lame split of the B-bar stiffness (lame_stiffness.hpp under Volumetric::kBbar).
//
// B-bar's energy is mu |dev eps|^2 + kappa / 2 theta_bar^2 with kappa = lambda + 2 mu / 3 and
// theta_bar = Pi div u (volumetric_projection.hpp). With a spatial weight w(x) multiplying both
// moduli, and K_l, K_m the displacement formulation's Lame parts (lame_stiffness.hpp) under w,
//
//   K = -2 mu / 3 K_l + mu K_m + kappa V_w,   V_w = t C^T G_w C,   G_w[A, B] = int w N_A N_B,
//
// (the element kernel with lambda -> -2 mu / 3 is the deviatoric part, C the projection operator,
// N_A the projection space's functions, t the 2D thickness). Collecting lambda and mu,
//
//   K = lambda V_w + mu (K_m - 2/3 K_l + 2/3 V_w):
//
// still linear in the Lame parameters, with lambda part V_w and mu part K_m - 2/3 (K_l - V_w).
// For w = 1 this is assemble_stiffness's B-bar matrix; the projection itself does not depend on
// w (it is a property of the discretisation), only the Gram's weight does.
#include <Eigen/Sparse>
#include <vector>

#include "assembly_structure.hpp"
#include "isospring/analysis/lame_stiffness.hpp"

namespace isospring::analysis::detail {

/// V_w for every weight (an empty function is w = 1): full symmetric matrices over `dofs`.
std::vector<Eigen::SparseMatrix<double>> bbar_weighted_volumetric(
    const Problem& problem, const DofMap& dofs, const AssemblyStructure& structure,
    const std::vector<SpatialWeight>& weights);

/// Turns the displacement formulation's parts (under the same weight) into B-bar's, given V_w.
void make_bbar_lame_parts(const Eigen::SparseMatrix<double>& volumetric, LameStiffness& parts);

}  // namespace isospring::analysis::detail
