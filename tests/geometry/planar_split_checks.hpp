#pragma once
// Checks shared by the planar-split tests: conformity of a multipatch surface (every patch side is
// either the identical side of another patch, control points and weights, or on the boundary).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
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

/// The same for volumes: the boundary faces that no other patch shares (same control points and
/// weights up to a common factor, in any order), measured: the solid's surface area when every
/// interface conforms.
inline double unshared_face_area(const std::vector<nurbs::Patch>& volumes, double tolerance) {
  struct Side {
    std::vector<std::array<double, 4>> points;  // sorted (x, y, z, w / w of the first point)
    double area;
    size_t patch;
  };
  std::vector<Side> sides;
  for (size_t v = 0; v < volumes.size(); ++v)
    for (int dir = 0; dir < 3; ++dir)
      for (int end = 0; end < 2; ++end) {
        const nurbs::Patch face = boundary_side(volumes[v], dir, end);
        Side side{{}, measure(face), v};
        double w0 = 0.0;
        for (int i = 0; i < face.num_points(); ++i) w0 = std::max(w0, face.weight(i));
        for (int i = 0; i < face.num_points(); ++i) {
          const Eigen::Vector3d& x = face.control_point(i);
          side.points.push_back({x.x(), x.y(), x.z(), face.weight(i) / w0});
        }
        std::sort(side.points.begin(), side.points.end());
        sides.push_back(side);
      }
  auto same = [&](const Side& a, const Side& b) {
    if (a.points.size() != b.points.size()) return false;
    for (size_t i = 0; i < a.points.size(); ++i)
      for (int c = 0; c < 4; ++c)
        if (std::abs(a.points[i][c] - b.points[i][c]) > (c < 3 ? tolerance : 1e-12)) return false;
    return true;
  };
  double area = 0.0;
  for (size_t i = 0; i < sides.size(); ++i) {
    bool shared = false;
    for (size_t j = 0; j < sides.size() && !shared; ++j)
      shared = sides[j].patch != sides[i].patch && same(sides[i], sides[j]);
    if (!shared) area += sides[i].area;
  }
  return area;
}

}  // namespace isospring::geometry::test
