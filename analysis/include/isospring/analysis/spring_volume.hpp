#pragma once
// Volume (2D: area) terms of a spring network (SpringNetwork::volumes): the volume of a
// trilinear (bilinear) cell through its corner particles, its exact gradient and Hessian, and
// the energy, forces and stiffness of E = 1/2 (kappa / |V0|) (V(x) - V0)^2 per cell.
//
// V(x) = int_[0,1]^d det J dxi with J = sum_a x_a (grad_xi N_a)^T, N_a the (tri)linear corner
// functions. det J is of degree 2 in each parametric coordinate (each column of J is linear in
// the other coordinates), so 2-point Gauss per direction integrates V, dV/dx and d2V/dx2 exactly.
// State vectors are flat like spring_mechanics.hpp's (particle q, component c -> q * dim + c).
#include <Eigen/Core>
#include <Eigen/Sparse>
#include <vector>

#include "isospring/analysis/spring_network.hpp"

namespace isospring::analysis {

/// Number of corners of a cell of the network's dimension (4 or 8).
int volume_corners(int dimension);

/// V of one cell at the flat configuration x; `gradient` (corners * dim, corner-major) and
/// `hessian` (square of that) when not null.
double cell_volume(const VolumeTerm& term, const Eigen::VectorXd& x, int dimension,
                   Eigen::VectorXd* gradient = nullptr, Eigen::MatrixXd* hessian = nullptr);

/// The same at the network's rest positions (the value V0 should hold).
double rest_cell_volume(const SpringNetwork& network, const VolumeTerm& term,
                        Eigen::VectorXd* gradient = nullptr);

/// A shear term's (VolumeTerm::kind == kShear) energy mu |V0| |dev G|^2 at x, and its gradient
/// and Hessian over the corners (corner-major, like cell_volume) when not null.
double cell_shear_energy(const SpringNetwork& network, const VolumeTerm& term,
                         const Eigen::VectorXd& x, Eigen::VectorXd* gradient = nullptr,
                         Eigen::MatrixXd* hessian = nullptr);

/// The term's stiffness at rest per unit modulus as rank-one columns over its corners
/// (volume_dofs order): K_rest = modulus sum_k g_k g_k^T. A volume term has one column,
/// b / sqrt(|V0|); a shear term one per deviatoric strain mode (5 in 3D, 2 in 2D),
/// g_k = sqrt(2 / |V0|) (D_k b_a)_a with D_k an orthonormal basis of the symmetric deviatoric
/// tensors. The fits treat every column as an element k g g^T sharing the term's parameter.
std::vector<Eigen::VectorXd> rest_stiffness_columns(const SpringNetwork& network,
                                                    const VolumeTerm& term);

/// sum over the cell terms of 1/2 (kappa / |V0|) (V(x) - V0)^2 (volume terms) and
/// mu |V0| |dev G|^2 (shear terms).
double volume_energy(const SpringNetwork& network, const Eigen::VectorXd& x);

/// Adds -dE/dx of the cell terms (volume and shear) to f (sized like x).
void add_volume_forces(const SpringNetwork& network, const Eigen::VectorXd& x, Eigen::VectorXd& f);

/// Appends the tangent d2E/dx2 = (kappa / |V0|) (b b^T + (V - V0) d2V/dx2) per cell at x
/// (`at_rest`: b b^T at the rest positions only, the linearised stiffness at rest); shear terms:
/// their exact Hessian (at rest: the sum of rest_stiffness_columns' g g^T times mu).
void add_volume_stiffness(const SpringNetwork& network, const Eigen::VectorXd& x, bool at_rest,
                          std::vector<Eigen::Triplet<double>>& triplets);

/// Flat indices of a cell's corner components (corner-major), matching cell_volume's gradient.
std::vector<int> volume_dofs(const VolumeTerm& term, int dimension);

}  // namespace isospring::analysis
