#pragma once
// Gauss quadrature over the elements of a patch with the univariate B-spline values cached per
// direction: a quadrature point's rational basis is a tensor product of cached rows, so element
// loops never search spans or run the Cox-de Boor recursion.
#include <Eigen/Core>
#include <array>
#include <vector>

#include "isospring/nurbs/patch.hpp"

namespace isospring::analysis::detail {

/// Cached rule of one parametric direction: per element e and point q (index e * points + q) the
/// parameter, the Gauss weight times the span's half length, and the p+1 values and derivatives.
struct DirectionRule {
  int degree = 0;
  int points = 0;          // per element
  std::vector<int> spans;  // per element
  std::vector<double> params;
  std::vector<double> weights;
  std::vector<double> basis;  // [(e * points + q) * 2 * (p + 1) + k * (p + 1) + a], k = 0 / 1
};
/// `points` Gauss points in each non-empty span.
DirectionRule gauss_rule(const nurbs::KnotVector& knots, int points);
/// A single point at parameter u with weight 1 (integrates over a side where u is fixed).
DirectionRule fixed_rule(const nurbs::KnotVector& knots, double u);

/// Basis and geometry at one quadrature point.
struct QuadraturePoint {
  nurbs::Param param{0, 0, 0};
  double weight = 0.0;          // parametric weight (product of the direction weights)
  Eigen::VectorXd values;       // R_a, a over the element's control points
  Eigen::MatrixXd derivatives;  // dR_a/du_b, n x param_dim
  Eigen::Vector3d point;        // X
  Eigen::Matrix3d jacobian;     // dX/du, columns beyond param_dim are zero
};

class PatchQuadrature {
 public:
  /// rules[d] for d < patch.param_dim().
  PatchQuadrature(const nurbs::Patch& patch, std::array<DirectionRule, 3> rules);
  /// Gauss rule with `points` per direction (0: degree + 1 in each direction).
  static PatchQuadrature volume(const nurbs::Patch& patch, int points);
  /// Rule over side (dir, end): the other directions get Gauss rules.
  static PatchQuadrature side(const nurbs::Patch& patch, int dir, int end, int points);

  int num_elements() const { return num_elements_; }
  int points_per_element() const { return points_per_element_; }
  int basis_count() const { return basis_count_; }
  /// (i, j, k) element position from the flat element index (first direction fastest).
  std::array<int, 3> element_position(int element) const;
  /// Control-point indices of the element's basis, in the order of QuadraturePoint::values.
  void element_control_points(int element, int* out) const;
  void evaluate(int element, int point, QuadraturePoint& out) const;
  const nurbs::Patch& patch() const { return *patch_; }
  /// The cached rule of direction d (d < the patch's parametric dimension).
  const DirectionRule& rule(int d) const { return rules_[static_cast<size_t>(d)]; }

 private:
  const nurbs::Patch* patch_;
  std::array<DirectionRule, 3> rules_;
  int dim_ = 0;
  std::array<int, 3> elements_{1, 1, 1};
  std::array<int, 3> points_{1, 1, 1};
  std::array<int, 3> order_{1, 1, 1};  // p + 1 per direction (1 beyond param_dim)
  int num_elements_ = 0;
  int points_per_element_ = 0;
  int basis_count_ = 0;
};

}  // namespace isospring::analysis::detail
