// The ladder of background grids of an immersed case (immersed_grid_ladder.hpp).
#include "isospring/workflows/immersed_grid_ladder.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace isospring::workflows {

namespace {

Eigen::Vector3i cells_of(const geometry::ImmersedDomain& domain) {
  Eigen::Vector3i cells = Eigen::Vector3i::Ones();
  for (int d = 0; d < domain.background.param_dim(); ++d)
    cells[d] = domain.background.knots(d).num_elements();
  return cells;
}

// Level `level`'s cells per direction: level 0's times 2^(level / 2), rounded, and at least one
// more than the level before (so that every level is finer).
Eigen::Vector3i level_cells(const Eigen::Vector3i& cells0, int level) {
  Eigen::Vector3i cells = cells0;
  for (int l = 1; l <= level; ++l)
    for (int d = 0; d < 3; ++d)
      cells[d] =
          std::max(cells[d] + 1, static_cast<int>(std::lround(cells0[d] * std::pow(2.0, 0.5 * l))));
  return cells;
}

}  // namespace

std::optional<geometry::ImmersionOptions> immersed_ladder_grid(
    const geometry::ImmersionOptions& base, const geometry::ImmersedDomain& level0, int level,
    std::string* description) {
  if (level < 1) return std::nullopt;
  geometry::ImmersionOptions o = base;
  o.degree = level0.background.degree(0);
  const double factor = std::pow(2.0, 0.5 * level);
  const Eigen::Vector3i cells = level_cells(cells_of(level0), level);
  if (base.grading.empty()) {
    o.cells = cells;
    o.cell_size = 0.0;
  } else {  // the planes' grading from the base cell length of the level's spec
    if (base.cells.minCoeff() > 0)
      o.cells = level_cells(base.cells, level);
    else
      o.cell_size =
          (base.cell_size > 0.0 ? base.cell_size : level0.extent.maxCoeff() / 10.0) / factor;
    for (auto& plane : o.grading) plane.smallest /= factor;
  }
  if (description) {
    *description = "degree " + std::to_string(o.degree) + ", ";
    if (base.grading.empty())
      *description += std::to_string(cells[0]) + " x " + std::to_string(cells[1]) + " x " +
                      std::to_string(cells[2]) + " cells";
    else
      *description += "graded, cells " + std::to_string(factor).substr(0, 4) + " x smaller";
  }
  return o;
}

std::optional<long> immersed_ladder_dofs_bound(const geometry::ImmersionOptions& base,
                                               const geometry::ImmersedDomain& level0, int level) {
  if (!base.grading.empty() || level < 1) return std::nullopt;
  const int q = level0.background.degree(0);
  const Eigen::Vector3i cells0 = cells_of(level0), cells = level_cells(cells0, level);
  const Eigen::Vector3i points = cells + Eigen::Vector3i::Constant(q);
  // Per direction and level-0 element: the level's elements that overlap it (a relative 1e-9
  // keeps a shared cell face from counting as an overlap).
  auto overlapping = [&](int d, int e0) {
    const double r = static_cast<double>(cells[d]) / cells0[d];
    return std::pair<int, int>{
        static_cast<int>(std::floor(e0 * r + 1e-9)),
        std::min(cells[d], static_cast<int>(std::ceil((e0 + 1) * r - 1e-9)))};
  };
  std::vector<bool> active(static_cast<size_t>(points.prod()), false);
  for (const auto& cell : level0.cells) {
    const Eigen::Vector3i e0 = cell.span - Eigen::Vector3i::Constant(q);  // element index
    const auto [i0, i1] = overlapping(0, e0[0]);
    const auto [j0, j1] = overlapping(1, e0[1]);
    const auto [k0, k1] = overlapping(2, e0[2]);
    // Functions e .. e + q of each overlapping element e along each direction.
    for (int i = i0; i < i1 + q; ++i)
      for (int j = j0; j < j1 + q; ++j)
        for (int k = k0; k < k1 + q; ++k)
          active[static_cast<size_t>(i + points[0] * (j + points[1] * k))] = true;
  }
  return static_cast<long>(std::count(active.begin(), active.end(), true)) * level0.dimension;
}

fitting::ImmersedLadder immersed_grid_ladder(const geometry::CadSolid& solid,
                                             const geometry::ImmersionOptions& base,
                                             const geometry::ImmersedDomain& level0) {
  fitting::ImmersedLadder ladder;
  ladder.level = [&solid, &base, &level0](int level) {
    std::optional<fitting::ImmersedLevel> out;
    std::string description;
    const std::optional<geometry::ImmersionOptions> grid =
        immersed_ladder_grid(base, level0, level, &description);
    if (!grid) return out;
    const auto start = std::chrono::steady_clock::now();
    out = fitting::ImmersedLevel{geometry::immerse_solid(solid, *grid), description, 0.0};
    out->immersion_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return out;
  };
  ladder.dofs_bound = [&base, &level0](int level) {
    return immersed_ladder_dofs_bound(base, level0, level);
  };
  return ladder;
}

}  // namespace isospring::workflows
