#pragma once
// Evaluation of a patch at many parameters at once: points and first derivatives.
//
// Faster than calling Patch::derivatives() in a loop because the homogeneous control points are
// laid out once and the tensor product is contracted one direction at a time
// (O((p+1)(q+1)) 4-vector operations per point for a surface).
#include <Eigen/Core>
#include <array>
#include <vector>

#include "isospring/nurbs/patch.hpp"

namespace isospring::nurbs {

class BatchEvaluator {
 public:
  explicit BatchEvaluator(const Patch& patch);

  /// points.col(q) = X(params[q]); when `first` is not null, first->col(d*q + a) = dX/du_a with
  /// d the parametric dimension.
  void evaluate(const std::vector<Param>& params, Eigen::Matrix3Xd& points,
                Eigen::Matrix3Xd* first = nullptr) const;

 private:
  /// Per direction: what makes a basis evaluation division-free and its span search O(1) for
  /// (nearly) uniform knots.
  struct Direction {
    int degree = 0;
    const double* knots = nullptr;  // the patch's full knot vector
    std::vector<double> breaks;     // distinct knots
    std::vector<int> spans;         // span index of each element
    std::vector<double> inverses;   // per element: 1 / (t_{s+r+1} - t_{s+1-j+r}), j = 1..p, r < j
    double scale = 0.0;             // elements / parameter range, for the span guess
  };
  int locate(const Direction& direction, double u, int* element) const;
  void basis(const Direction& direction, int element, double u, double* out) const;

  const Patch& patch_;
  Eigen::Matrix4Xd homogeneous_;  // (w x, w y, w z, w) per control point, net order
  std::array<Direction, 3> directions_;
};

}  // namespace isospring::nurbs
