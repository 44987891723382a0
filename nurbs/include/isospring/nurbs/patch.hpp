#pragma once
// Tensor-product NURBS patches of parametric dimension 1 (curve), 2 (surface) or 3 (volume),
// embedded in 3D space (2D geometry has z = 0).
#include <Eigen/Core>
#include <array>
#include <vector>

#include "isospring/nurbs/knot_vector.hpp"

namespace isospring::nurbs {

/// Parametric coordinates (u, v, w); entries beyond the patch's parametric dimension are ignored.
using Param = std::array<double, 3>;

/// Point and parametric derivatives of a patch: first.col(a) = dX/du_a and
/// second[a].col(b) = d2X/(du_a du_b), zero beyond the parametric dimension.
struct PatchDerivatives {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Matrix3d first = Eigen::Matrix3d::Zero();
  std::array<Eigen::Matrix3d, 3> second{Eigen::Matrix3d::Zero(), Eigen::Matrix3d::Zero(),
                                        Eigen::Matrix3d::Zero()};
};

/// Non-zero rational basis functions R_i at a parameter: global control-point indices, values,
/// first derivatives (n x d, column a = dR/du_a) and, when asked for, second derivatives
/// (n x d*d, column a*d+b = d2R/(du_a du_b)).
struct RationalBasis {
  std::vector<int> indices;
  Eigen::VectorXd values;
  Eigen::MatrixXd first;
  Eigen::MatrixXd second;
};

class Patch {
 public:
  Patch() = default;
  /// knots.size() is the parametric dimension (1..3). Control points are ordered with the first
  /// parametric direction fastest. Empty weights mean all 1 (a polynomial B-spline).
  /// Throws InputError when the sizes disagree or a weight is not positive and finite.
  Patch(std::vector<KnotVector> knots, std::vector<Eigen::Vector3d> control_points,
        std::vector<double> weights = {});

  int param_dim() const { return static_cast<int>(knots_.size()); }
  const KnotVector& knots(int dir) const { return knots_[static_cast<size_t>(dir)]; }
  const std::vector<KnotVector>& all_knots() const { return knots_; }
  int degree(int dir) const { return knots(dir).degree(); }
  /// Control points along a direction (1 beyond the parametric dimension).
  int num_points(int dir) const { return dir < param_dim() ? knots(dir).num_basis() : 1; }
  int num_points() const { return static_cast<int>(points_.size()); }
  int index(int i, int j = 0, int k = 0) const {
    return i + num_points(0) * (j + num_points(1) * k);
  }
  /// Inverse of index(): the (i, j, k) position of a control point in the net.
  std::array<int, 3> net_position(int index) const;

  const std::vector<Eigen::Vector3d>& control_points() const { return points_; }
  const Eigen::Vector3d& control_point(int index) const {
    return points_[static_cast<size_t>(index)];
  }
  void set_control_point(int index, const Eigen::Vector3d& x) {
    points_[static_cast<size_t>(index)] = x;
  }
  const std::vector<double>& weights() const { return weights_; }
  double weight(int index) const { return weights_[static_cast<size_t>(index)]; }
  bool is_rational() const;
  /// 2 when every control point has z == 0 and the patch is at most a surface, else 3.
  int physical_dim() const;
  /// Parameter range [first knot, last knot] of a direction.
  double param_min(int dir) const { return knots(dir).first(); }
  double param_max(int dir) const { return knots(dir).last(); }
  /// Number of non-empty elements (knot spans) in total and per direction.
  int num_elements() const;

  Eigen::Vector3d point(const Param& u) const;
  /// Point with first (order >= 1) and second (order >= 2) derivatives.
  PatchDerivatives derivatives(const Param& u, int order = 1) const;
  /// Rational basis with derivatives up to `order` (0, 1 or 2).
  RationalBasis basis(const Param& u, int order = 1) const;

  /// Axis-aligned bounding box of the control net (contains the patch: convex hull property).
  std::pair<Eigen::Vector3d, Eigen::Vector3d> control_bounds() const;

 private:
  std::vector<KnotVector> knots_;
  std::vector<Eigen::Vector3d> points_;
  std::vector<double> weights_;
};

}  // namespace isospring::nurbs
