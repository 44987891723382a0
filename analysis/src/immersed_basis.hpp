#pragma once
// The background B-spline basis of an immersed domain evaluated at physical points: the grid is
// an affine box (in the domain's frame), so parameters follow from coordinates directly and
// physical derivatives are the parametric ones times a constant per direction, turned from the
// grid's axes to the world's.
#include <Eigen/Core>
#include <array>
#include <vector>

#include "isospring/geometry/immersed_domain.hpp"

namespace isospring::analysis::detail {

using Element = std::array<int, 3>;  // element index per direction (0 beyond the dimension)

struct BasisAt {
  std::vector<int> control_points;  // (p+1)^d, first direction fastest
  Eigen::VectorXd values;
  Eigen::MatrixXd gradients;  // count x dim, physical
};

class BackgroundBasis {
 public:
  /// Throws nurbs::InputError when the background is not the affine box origin + extent * u of
  /// polynomial B-splines (rational weights that are not all equal, misplaced control points).
  /// `validate` = false skips the control-point check (for a domain already checked).
  explicit BackgroundBasis(const geometry::ImmersedDomain& domain, bool validate = true);

  int dim() const { return dim_; }
  int degree(int d) const { return patch_->degree(d); }
  int count() const { return count_; }
  int elements(int d) const {
    return d < dim_ ? static_cast<int>(spans_[static_cast<size_t>(d)].size()) : 1;
  }
  int flat(const Element& e) const { return e[0] + elements(0) * (e[1] + elements(1) * e[2]); }
  /// The element containing x (the upper one on a grid line), clamped to the grid.
  Element element_of(const Eigen::Vector3d& x) const;
  /// Grid coordinates (along the frame's axes) of a world point, and back.
  Eigen::Vector3d to_grid(const Eigen::Vector3d& x) const {
    return rotated_ ? Eigen::Vector3d(frame_.transpose() * x) : x;
  }
  Eigen::Vector3d to_world(const Eigen::Vector3d& y) const {
    return rotated_ ? Eigen::Vector3d(frame_ * y) : y;
  }
  /// Bounds of an element in grid coordinates.
  Eigen::Vector3d element_lo(const Element& e) const;
  Eigen::Vector3d element_hi(const Element& e) const;
  /// Control points of the element's basis, in the order of BasisAt.
  void control_points(const Element& e, std::vector<int>& out) const;
  /// Values and physical (world) gradients of the element's basis at world point x (x may lie on
  /// its closure).
  void evaluate(const Element& e, const Eigen::Vector3d& x, BasisAt& out) const;
  /// The k-th derivative along the grid's axis `dir` of the element's basis at world point x,
  /// from the element's polynomial pieces.
  void directional_derivative(const Element& e, const Eigen::Vector3d& x, int dir, int k,
                              Eigen::VectorXd& out) const;

 private:
  double param(int d, double x) const;
  const nurbs::Patch* patch_;
  int dim_;
  int count_ = 1;
  Eigen::Vector3d origin_, extent_;
  Eigen::Matrix3d frame_;                  // the grid's axes in the world (ImmersedDomain::frame)
  bool rotated_ = false;                   // frame_ is not the identity
  std::array<std::vector<int>, 3> spans_;  // knot-span index of each element
  std::array<double, 3> scale_{1, 1, 1};   // du/dx per direction
};

}  // namespace isospring::analysis::detail
