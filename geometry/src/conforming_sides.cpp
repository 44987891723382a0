// Shared straight sides of independently cut faces made conforming (see conforming_sides.hpp).
#include "isospring/geometry/conforming_sides.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "isospring/nurbs/refine.hpp"

namespace isospring::geometry {

namespace {

using Eigen::Vector3d;
using nurbs::Patch;

struct SideRef {
  size_t patch;
  int dir, end;  // the side at the `end` of direction `dir`; it runs along 1 - dir
};

Vector3d corner(const Patch& p, int dir, int end, int at) {
  nurbs::Param u{0, 0, 0};
  u[static_cast<size_t>(dir)] = end ? p.param_max(dir) : p.param_min(dir);
  const int along = 1 - dir;
  u[static_cast<size_t>(along)] = at ? p.param_max(along) : p.param_min(along);
  return p.point(u);
}

// Every control point of the side on the chord between its end points.
bool straight_side(const Patch& p, int dir, int end, double tolerance) {
  const Vector3d a = corner(p, dir, end, 0), b = corner(p, dir, end, 1);
  const double length = (b - a).norm();
  if (length <= tolerance) return false;
  const Vector3d t = (b - a) / length;
  const int layer = end ? p.num_points(dir) - 1 : 0;
  for (int i = 0; i < p.num_points(); ++i) {
    if (p.net_position(i)[static_cast<size_t>(dir)] != layer) continue;
    const Vector3d x = p.control_point(i) - a;
    if ((x - x.dot(t) * t).norm() > tolerance) return false;
  }
  return true;
}

// Interior knots of a direction in [0, 1] with their multiplicities (reversed: t -> 1 - t).
std::map<double, int> normalised_knots(const Patch& p, int along, bool reversed) {
  const nurbs::KnotVector& k = p.knots(along);
  const std::vector<double> values = k.unique();
  const std::vector<int> mult = k.multiplicities();
  std::map<double, int> out;
  for (size_t i = 1; i + 1 < values.size(); ++i) {
    double t = (values[i] - k.first()) / (k.last() - k.first());
    if (reversed) t = 1.0 - t;
    out[t] = mult[i];
  }
  return out;
}

// Raises `p` along `along` to `degree` and its interior knots to at least the multiplicities of
// `wanted` (normalised, merged with existing knots within 1e-10). True when it changed.
bool refine_to(Patch& p, int along, bool reversed, int degree,
               const std::map<double, int>& wanted) {
  bool changed = false;
  if (p.degree(along) < degree) {
    p = nurbs::elevate_degree(p, along, degree - p.degree(along));
    changed = true;
  }
  const std::map<double, int> have = normalised_knots(p, along, reversed);
  for (const auto& [t, m] : wanted) {
    int present = 0;
    for (const auto& [s, n] : have)
      if (std::abs(s - t) <= 1e-10) present = n;
    if (present >= m) continue;
    const nurbs::KnotVector& k = p.knots(along);
    const double u = k.first() + (reversed ? 1.0 - t : t) * (k.last() - k.first());
    p = nurbs::insert_knot(p, along, u, m - present);
    changed = true;
  }
  return changed;
}

}  // namespace

std::vector<Patch> conform_shared_sides(std::vector<Patch> patches, double tolerance) {
  for (size_t round = 0; round <= patches.size(); ++round) {
    std::vector<SideRef> sides;
    for (size_t p = 0; p < patches.size(); ++p)
      if (patches[p].param_dim() == 2)
        for (int dir = 0; dir < 2; ++dir)
          for (int end = 0; end < 2; ++end)
            if (straight_side(patches[p], dir, end, tolerance)) sides.push_back({p, dir, end});
    bool changed = false;
    for (size_t i = 0; i < sides.size(); ++i)
      for (size_t j = i + 1; j < sides.size(); ++j) {
        const SideRef &a = sides[i], &b = sides[j];
        if (a.patch == b.patch) continue;
        Patch &pa = patches[a.patch], &pb = patches[b.patch];
        const Vector3d a0 = corner(pa, a.dir, a.end, 0), a1 = corner(pa, a.dir, a.end, 1);
        const Vector3d b0 = corner(pb, b.dir, b.end, 0), b1 = corner(pb, b.dir, b.end, 1);
        bool reversed = false;
        if ((a0 - b1).norm() <= tolerance && (a1 - b0).norm() <= tolerance)
          reversed = true;
        else if (!((a0 - b0).norm() <= tolerance && (a1 - b1).norm() <= tolerance))
          continue;
        const int along_a = 1 - a.dir, along_b = 1 - b.dir;
        const int degree = std::max(pa.degree(along_a), pb.degree(along_b));
        // Degree elevation raises interior multiplicities, so the union of both sides' knots
        // (in a's parameter; b's mapped through the orientation) is taken after it.
        bool changed_here = refine_to(pa, along_a, false, degree, {});
        changed_here |= refine_to(pb, along_b, reversed, degree, {});
        std::map<double, int> wanted = normalised_knots(pa, along_a, false);
        for (const auto& knot : normalised_knots(pb, along_b, reversed)) {
          const double t = knot.first;  // a plain variable: clang 14 cannot capture a binding
          auto close = std::find_if(wanted.begin(), wanted.end(),
                                    [t](const auto& w) { return std::abs(w.first - t) <= 1e-10; });
          if (close == wanted.end())
            wanted[t] = knot.second;
          else
            close->second = std::max(close->second, knot.second);
        }
        changed_here |= refine_to(pa, along_a, false, degree, wanted);
        changed_here |= refine_to(pb, along_b, reversed, degree, wanted);
        changed = changed || changed_here;
      }
    if (!changed) return patches;
  }
  return patches;
}

}  // namespace isospring::geometry
