#pragma once
// Corotated (rotation-extracted) linear forces of a spring network.
//
// The linear forces -K_0 (x - X) - C_0 v of the network linearised at rest (rest_stiffness,
// rest_damping) see a finite rotation as a strain: a rigidly rotated body is pushed back. Here
// each particle i measures the rotation R_i of its neighbourhood (the particles its block row of
// K_0 couples it to) by shape matching [Mueller et al., "Meshless deformations based on shape
// matching", SIGGRAPH 2005]: R_i is the rotation of the polar decomposition of the
// neighbourhood's least-squares deformation gradient
//   F_i = A_i S_i^-1,  A_i = sum_j (x_j - x_i)(X_j - X_i)^T,  S_i = sum_j (X_j - X_i)(X_j - X_i)^T
// (exact for affine motions, so a pure stretch is no rotation),
// and its block row of the linear forces is evaluated in that frame and rotated back (stiffness
// warping [Mueller, Dorsey, McMillan, Jaillet & Cutler, "Stable real-time deformations",
// SCA 2002]):
//   f_i = -R_i sum_j K_ij (R_i^T x_j - X_j) - R_i sum_j C_ij R_i^T v_j.
// The row blocks of K_0 and C_0 sum to zero (translations are free), so this is written over the
// differences x_j - x_i, which makes it exactly zero for every rigid motion x = Q X + t,
// v = w x (x - c): F_i = Q gives R_i = Q. With every R_i = I it IS the linear force. It is
// not the gradient of an energy (rotations of neighbouring particles differ), as in corotated
// FEM with per-vertex rotations; near rest it differs from the linear force by O(|u|^2).
//
// Cost per evaluation: one 3 x 3 polar decomposition per particle and two 3 x 3 products per
// nonzero block of K_0: O(n) for a network of bounded connectivity.
#include <Eigen/Core>
#include <vector>

#include "isospring/analysis/spring_network.hpp"

namespace isospring::analysis {

/// The rotation R of the polar decomposition A = R S (R proper orthogonal, S symmetric):
/// Higham's scaled Newton iteration R <- (R + R^-T) / 2 while det A > 0, the SVD (with the
/// reflection turned into a rotation) for a flat or inverted A. Exact for A = Q S with S
/// symmetric positive definite, to round-off.
Eigen::Matrix3d polar_rotation(const Eigen::Matrix3d& a);

class CorotatedForces {
 public:
  /// Block rows of K_0 and C_0 over all particles (fixed ones included). Throws
  /// nurbs::InputError when a particle with terms has no neighbour to measure its rotation.
  explicit CorotatedForces(const SpringNetwork& network);

  int dimension() const { return dim_; }
  int particles() const { return static_cast<int>(offsets_.size()) - 1; }

  /// R_i at positions x (flat, particles x dimension); 2D rotations are about z.
  void rotations(const Eigen::VectorXd& x, std::vector<Eigen::Matrix3d>& out) const;

  /// f (flat, overwritten) at positions x and velocities v (v empty: no damping).
  void forces(const Eigen::VectorXd& x, const Eigen::VectorXd& v, Eigen::VectorXd& f) const;

  /// The same with given rotations; with `rest_offsets` false the rest term X_j - X_i is left out,
  /// which gives the force's derivative at frozen rotations, df = -R K R^T dx - R C R^T dv.
  void rotated_forces(const std::vector<Eigen::Matrix3d>& rotations, const Eigen::VectorXd& x,
                      const Eigen::VectorXd& v, bool rest_offsets, Eigen::VectorXd& f) const;

  /// Block storage (for export): particle i's neighbours are columns()[offsets()[i] ..
  /// offsets()[i+1]) (i itself excluded), with the d x d blocks K_ij and C_ij row-major at the
  /// same positions times d^2; row_sum_stiffness/damping hold sum_j K_ij, sum_j C_ij per
  /// particle (zero up to round-off; kept so that R = I gives K_0 x exactly).
  const std::vector<int>& offsets() const { return offsets_; }
  const std::vector<int>& columns() const { return columns_; }
  const std::vector<double>& stiffness_blocks() const { return stiffness_; }
  const std::vector<double>& damping_blocks() const { return damping_; }
  const std::vector<double>& row_sum_stiffness() const { return row_k_; }
  const std::vector<double>& row_sum_damping() const { return row_c_; }
  const Eigen::VectorXd& rest() const { return rest_; }
  /// S_i^-1 (pseudo-inverse, 3 x 3, zero third row and column in 2D) per particle.
  const std::vector<Eigen::Matrix3d>& rest_inverse() const { return rest_inverse_; }

 private:
  int dim_ = 3;
  Eigen::VectorXd rest_;
  std::vector<int> offsets_, columns_;
  std::vector<double> stiffness_, damping_, row_k_, row_c_;
  std::vector<Eigen::Matrix3d> k3_, c3_, row_k3_, row_c3_;  // the same, padded to 3 x 3
  std::vector<Eigen::Matrix3d> rest_inverse_;  // (sum_j d_j d_j^T)^+ per particle, d_j = X_j - X_i
  Eigen::Matrix3d neighbourhood_inverse(int i) const;
  Eigen::Vector3d rest_point(int i) const;
};

}  // namespace isospring::analysis
