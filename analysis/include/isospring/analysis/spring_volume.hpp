#pragma once
// Volume (2D: area) terms of a spring network (SpringNetwork::volumes, issue 14): the volume of a
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

/// sum over the volume terms of 1/2 (kappa / |V0|) (V(x) - V0)^2.
double volume_energy(const SpringNetwork& network, const Eigen::VectorXd& x);

/// Adds -dE/dx of the volume terms to f (sized like x).
void add_volume_forces(const SpringNetwork& network, const Eigen::VectorXd& x, Eigen::VectorXd& f);

/// Appends the tangent d2E/dx2 = (kappa / |V0|) (b b^T + (V - V0) d2V/dx2) per cell at x
/// (`at_rest`: b b^T at the rest positions only, the linearised stiffness at rest).
void add_volume_stiffness(const SpringNetwork& network, const Eigen::VectorXd& x, bool at_rest,
                          std::vector<Eigen::Triplet<double>>& triplets);

/// Flat indices of a cell's corner components (corner-major), matching cell_volume's gradient.
std::vector<int> volume_dofs(const VolumeTerm& term, int dimension);

}  // namespace isospring::analysis
