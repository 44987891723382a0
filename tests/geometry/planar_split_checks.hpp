#pragma once
// Checks shared by the planar-split tests: conformity of a multipatch surface (every patch side is
// either the identical side of another patch, control points and weights, or on the boundary).
#include <gtest/gtest.h>

#include <vector>

#include "isospring/geometry/cad.hpp"
#include "isospring/geometry/measure.hpp"
#include "isospring/nurbs/patch.hpp"

namespace isospring::geometry::test {

// Two sides are the same side when their control points and weights agree, in order or reversed.
inline bool same_side(const nurbs::Patch& a, const nurbs::Patch& b, double tolerance) {
  if (a.num_points() != b.num_points() || a.knots(0).degree() != b.knots(0).degree()) return false;
  for (int reversed = 0; reversed < 2; ++reversed) {
    bool same = true;
    for (int i = 0; i < a.num_points() && same; ++i) {
      const int j = reversed ? a.num_points() - 1 - i : i;
      const double ratio = a.weight(0) / b.weight(reversed ? b.num_points() - 1 : 0);
      same = (a.control_point(i) - b.control_point(j)).norm() <= tolerance &&
             std::abs(a.weight(i) - ratio * b.weight(j)) <= 1e-12 * a.weight(i);
    }
    if (same) return true;
  }
  return false;
}

/// Total length of the sides that no other patch shares: for a conforming cut it is the
/// perimeter of the region (outline and holes); a side glued to nothing inside the region (a
/// T-junction, different knots or weights across an interface) adds its length.
inline double unshared_side_length(const std::vector<nurbs::Patch>& patches, double tolerance) {
  std::vector<nurbs::Patch> sides;
  for (const auto& p : patches)
    for (int dir = 0; dir < 2; ++dir)
      for (int end = 0; end < 2; ++end) sides.push_back(boundary_side(p, dir, end));
  double length = 0.0;
  for (size_t i = 0; i < sides.size(); ++i) {
    bool shared = false;
    for (size_t j = 0; j < sides.size() && !shared; ++j)
      shared = j / 4 != i / 4 && same_side(sides[i], sides[j], tolerance);
    if (!shared) length += measure(sides[i]);
  }
  return length;
}

}  // namespace isospring::geometry::test
