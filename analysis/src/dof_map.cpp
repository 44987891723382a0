// Node numbering with conforming-interface gluing by side matching.
#include "isospring/analysis/dof_map.hpp"

#include <Eigen/Geometry>
#include <numeric>

#include "isospring/analysis/sides.hpp"
#include "isospring/nurbs/quadrature.hpp"

namespace isospring::analysis {

int spatial_dimension(Formulation formulation) {
  return formulation == Formulation::kSolid ? 3 : 2;
}

namespace {

struct SideGrid {
  int patch = 0;
  int dir = 0;
  int end = 0;
  std::array<int, 2> size{0, 0};
  std::vector<int> points;
  Eigen::Vector3d lo, hi;
};

int find_root(std::vector<int>& parent, int i) {
  while (parent[static_cast<size_t>(i)] != i) {
    parent[static_cast<size_t>(i)] = parent[static_cast<size_t>(parent[static_cast<size_t>(i)])];
    i = parent[static_cast<size_t>(i)];
  }
  return i;
}

// Position in b's grid of point (i, j) of a's grid under orientation `o` (bit 0: flip the first
// index, bit 1: flip the second, bit 2: transpose).
std::array<int, 2> oriented(int i, int j, int o, const std::array<int, 2>& b_size) {
  if (o & 4) std::swap(i, j);
  if (o & 1) i = b_size[0] - 1 - i;
  if (o & 2) j = b_size[1] - 1 - j;
  return {i, j};
}

// Measure (length of a curve side, area of a surface side) and centroid of a patch side: Gauss
// with 4 points per knot span along the side's directions.
std::pair<double, Eigen::Vector3d> side_moments(const nurbs::Patch& patch, int dir, int end) {
  const nurbs::GaussRule rule = nurbs::gauss_legendre(4);
  std::vector<int> along;
  for (int d = 0; d < patch.param_dim(); ++d)
    if (d != dir) along.push_back(d);
  std::array<std::vector<std::pair<double, double>>, 2> points;  // (parameter, weight)
  for (size_t a = 0; a < along.size(); ++a) {
    const std::vector<double> breaks = patch.knots(along[a]).unique();
    for (size_t e = 0; e + 1 < breaks.size(); ++e)
      for (size_t g = 0; g < rule.points.size(); ++g) {
        const double h = (breaks[e + 1] - breaks[e]) / 2.0;
        points[a].push_back({breaks[e] + (rule.points[g] + 1.0) * h, rule.weights[g] * h});
      }
  }
  if (along.size() < 2) points[1] = {{0.0, 1.0}};
  double measure = 0.0;
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  for (const auto& [s, ws] : points[0])
    for (const auto& [t, wt] : points[1]) {
      nurbs::Param u{0, 0, 0};
      u[static_cast<size_t>(dir)] = end ? patch.param_max(dir) : patch.param_min(dir);
      u[static_cast<size_t>(along[0])] = s;
      if (along.size() > 1) u[static_cast<size_t>(along[1])] = t;
      const nurbs::PatchDerivatives d = patch.derivatives(u);
      const Eigen::Vector3d ds = d.first.col(along[0]);
      const double jacobian =
          along.size() > 1 ? ds.cross(Eigen::Vector3d(d.first.col(along[1]))).norm() : ds.norm();
      measure += ws * wt * jacobian;
      moment += ws * wt * jacobian * d.point;
    }
  return {measure, measure > 0.0 ? Eigen::Vector3d(moment / measure) : Eigen::Vector3d::Zero()};
}

}  // namespace

DofMap::DofMap(const Problem& problem, double relative_tolerance)
    : dofs_per_node_(spatial_dimension(problem.formulation)) {
  const int num_patches = static_cast<int>(problem.patches.size());
  std::vector<int> offset(static_cast<size_t>(num_patches) + 1, 0);
  for (int p = 0; p < num_patches; ++p)
    offset[static_cast<size_t>(p) + 1] =
        offset[static_cast<size_t>(p)] + problem.patches[static_cast<size_t>(p)].num_points();
  const int total = offset.back();
  std::vector<int> parent(static_cast<size_t>(total));
  std::iota(parent.begin(), parent.end(), 0);

  if (num_patches > 0) {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
    for (const auto& patch : problem.patches) {
      const auto [plo, phi] = patch.control_bounds();
      lo = lo.cwiseMin(plo);
      hi = hi.cwiseMax(phi);
    }
    const double tol = relative_tolerance * (hi - lo).norm();
    std::vector<SideGrid> sides;
    for (int p = 0; p < num_patches; ++p) {
      const auto& patch = problem.patches[static_cast<size_t>(p)];
      for (int dir = 0; dir < patch.param_dim(); ++dir)
        for (int end = 0; end < 2; ++end) {
          SideGrid s{p, dir, end, {0, 0}, {}, {}, {}};
          s.points = side_control_points(patch, dir, end, &s.size);
          s.lo = s.hi = patch.control_point(s.points.front());
          for (int i : s.points) {
            s.lo = s.lo.cwiseMin(patch.control_point(i));
            s.hi = s.hi.cwiseMax(patch.control_point(i));
          }
          sides.push_back(std::move(s));
        }
    }
    auto point = [&](const SideGrid& s, int i, int j) -> const Eigen::Vector3d& {
      return problem.patches[static_cast<size_t>(s.patch)].control_point(
          s.points[static_cast<size_t>(i + s.size[0] * j)]);
    };
    for (size_t a = 0; a < sides.size(); ++a)
      for (size_t b = a + 1; b < sides.size(); ++b) {
        const SideGrid& sa = sides[a];
        const SideGrid& sb = sides[b];
        if (!problem.glue_patch_seams && sa.patch == sb.patch) continue;
        if ((sa.lo - sb.lo).cwiseAbs().maxCoeff() > tol ||
            (sa.hi - sb.hi).cwiseAbs().maxCoeff() > tol)
          continue;
        // A side whose points all coincide (a collapsed pole) matches nothing meaningfully.
        if ((sa.hi - sa.lo).norm() <= tol) continue;
        bool glued = false;
        for (int o = 0; o < 8 && sa.points.size() == sb.points.size(); ++o) {
          const bool transpose = (o & 4) != 0;
          const std::array<int, 2> shape =
              transpose ? std::array<int, 2>{sa.size[1], sa.size[0]} : sa.size;
          if (shape != sb.size) continue;
          bool match = true;
          for (int j = 0; j < sa.size[1] && match; ++j)
            for (int i = 0; i < sa.size[0] && match; ++i) {
              const auto [bi, bj] = oriented(i, j, o, sb.size);
              match = (point(sa, i, j) - point(sb, bi, bj)).norm() <= tol;
            }
          if (!match) continue;
          for (int j = 0; j < sa.size[1]; ++j)
            for (int i = 0; i < sa.size[0]; ++i) {
              const auto [bi, bj] = oriented(i, j, o, sb.size);
              const int ga = offset[static_cast<size_t>(sa.patch)] +
                             sa.points[static_cast<size_t>(i + sa.size[0] * j)];
              const int gb = offset[static_cast<size_t>(sb.patch)] +
                             sb.points[static_cast<size_t>(bi + sb.size[0] * bj)];
              const int ra = find_root(parent, ga), rb = find_root(parent, gb);
              if (ra != rb) {
                parent[static_cast<size_t>(std::max(ra, rb))] = std::min(ra, rb);
                ++glued_pairs_;
              }
            }
          glued = true;
          break;
        }
        if (glued || sa.patch == sb.patch) continue;
        // Same box but not glued: do the two sides lie on each other (same measure and
        // centroid)? Then the interface is non-conforming.
        const auto [measure_a, centroid_a] =
            side_moments(problem.patches[static_cast<size_t>(sa.patch)], sa.dir, sa.end);
        const auto [measure_b, centroid_b] =
            side_moments(problem.patches[static_cast<size_t>(sb.patch)], sb.dir, sb.end);
        if (std::abs(measure_a - measure_b) <= 1e-6 * std::max(measure_a, measure_b) &&
            (centroid_a - centroid_b).norm() <= tol)
          unglued_.push_back({sa.patch, sa.dir, sa.end, sb.patch, sb.dir, sb.end});
      }
  }

  // Number the roots in control-point order.
  std::vector<int> number(static_cast<size_t>(total), -1);
  node_.resize(static_cast<size_t>(num_patches));
  for (int p = 0; p < num_patches; ++p) {
    const auto& patch = problem.patches[static_cast<size_t>(p)];
    auto& nodes = node_[static_cast<size_t>(p)];
    nodes.resize(static_cast<size_t>(patch.num_points()));
    for (int i = 0; i < patch.num_points(); ++i) {
      const int root = find_root(parent, offset[static_cast<size_t>(p)] + i);
      if (number[static_cast<size_t>(root)] < 0) {
        number[static_cast<size_t>(root)] = num_nodes_++;
        positions_.push_back(patch.control_point(i));
      }
      nodes[static_cast<size_t>(i)] = number[static_cast<size_t>(root)];
    }
  }
}

}  // namespace isospring::analysis
