#pragma once
// Mechanics of a mass-spring network (nmsm.md "Spring model"): energy, forces, analytic tangent
// stiffness, the linearised stiffness at rest and damping coefficients.
//
// State vectors are flat: particle q, component c -> entry q * dimension + c, with dimension the
// network's (2: in-plane, z ignored; 3). Matrices are full (both triangles) and sparse.
#include <Eigen/Core>
#include <Eigen/Sparse>
#include <vector>

#include "isospring/analysis/spring_network.hpp"

namespace isospring::analysis {

/// Rest positions as a flat vector.
Eigen::VectorXd flat_positions(const SpringNetwork& network);

/// E = 1/2 sum_s k_s (|x_i - x_j| - L0_s)^2 at the configuration x, plus the volume terms'
/// energy (spring_volume.hpp) when the network has any; so are the forces and stiffnesses below.
double spring_energy(const SpringNetwork& network, const Eigen::VectorXd& x);

/// Elastic forces -dE/dx (a zero-length spring contributes nothing: it has no direction).
Eigen::VectorXd spring_forces(const SpringNetwork& network, const Eigen::VectorXd& x);

/// Damping forces along the springs: -c_s ((l . dl/dt) / |l|) l / |l| on particle i, opposite on j.
Eigen::VectorXd damping_forces(const SpringNetwork& network, const Eigen::VectorXd& x,
                               const Eigen::VectorXd& v);

/// spring_forces and damping_forces in one pass over the springs, written into f_spring and
/// f_damping (resized to x's size; no allocation when they already have it). The explicit
/// integrator's inner loop: each result is bit-for-bit the separate function's.
void spring_and_damping_forces(const SpringNetwork& network, const Eigen::VectorXd& x,
                               const Eigen::VectorXd& v, Eigen::VectorXd& f_spring,
                               Eigen::VectorXd& f_damping);

/// Tangent stiffness d^2E/dx^2 at x: per spring k [n n^T + (1 - L0/|l|) (I - n n^T)] on the (i,i)
/// and (j,j) blocks and its negative on (i,j), (j,i).
Eigen::SparseMatrix<double> tangent_stiffness(const SpringNetwork& network,
                                              const Eigen::VectorXd& x);

/// Linearised stiffness at rest, K = sum_s k_s g_s g_s^T (g_s: n_s on i, -n_s on j).
Eigen::SparseMatrix<double> rest_stiffness(const SpringNetwork& network);

/// Linear damping matrix along the rest directions, C = sum_s c_s g_s g_s^T (the derivative of
/// damping_forces with respect to v at rest, negated).
Eigen::SparseMatrix<double> rest_damping(const SpringNetwork& network);

/// Lumped mass matrix diagonal: m_q repeated per component.
Eigen::VectorXd mass_diagonal(const SpringNetwork& network);

/// Mass-proportional damping per spring [S15 4.18]: c = (1/alpha) 2 sqrt(k (m_i + m_j)) / L0.
/// Throws nurbs::InputError unless alpha > 0.
void assign_damping_alpha(SpringNetwork& network, double alpha);

/// Damping by a ratio zeta of each spring's critical damping with the two-body reduced mass:
/// c = 2 zeta sqrt(k m_i m_j / (m_i + m_j)), or c = 2 zeta sqrt(k m) with the free particle's
/// mass m when the other end is fixed: zeta is then the damping ratio of that spring's own
/// oscillation (of a lone spring exactly; in a network, per spring). Throws nurbs::InputError
/// unless zeta >= 0.
void assign_damping_ratio(SpringNetwork& network, double zeta);

/// Flat indices of the components of the fixed particles.
std::vector<int> fixed_dofs(const SpringNetwork& network);

}  // namespace isospring::analysis
