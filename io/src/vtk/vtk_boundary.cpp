// Which sides of a solid model are its outer surface, and how finely to sample them
// (vtk_boundary.hpp); the writer is in vtk_sampled.cpp beside the volume's.
#include "isospring/io/vtk_boundary.hpp"

#include <algorithm>

#include "isospring/analysis/dof_map.hpp"
#include "isospring/analysis/sides.hpp"

namespace isospring::io {

std::vector<PatchSide> outer_sides(const analysis::Problem& problem) {
  const std::vector<std::array<bool, 6>> inner =
      analysis::inner_sides(problem.patches, analysis::DofMap(problem));
  std::vector<PatchSide> sides;
  for (size_t p = 0; p < problem.patches.size(); ++p) {
    if (problem.patches[p].param_dim() != 3) continue;
    for (int dir = 0; dir < 3; ++dir)
      for (int end = 0; end < 2; ++end)
        if (!inner[p][static_cast<size_t>(2 * dir + end)])
          sides.push_back({static_cast<int>(p), dir, end});
  }
  return sides;
}

int boundary_samples(const std::vector<nurbs::Patch>& patches, const std::vector<PatchSide>& sides,
                     int most, double points_per_control_point, double small_model_points) {
  double control_points = 0;
  for (const nurbs::Patch& patch : patches) control_points += patch.num_points();
  // Points of a side sampled s times per element: (s e_a + 1)(s e_b + 1) over its directions.
  auto points = [&](int s) {
    double total = 0;
    for (const PatchSide& side : sides) {
      const nurbs::Patch& patch = patches.at(static_cast<size_t>(side.patch));
      double n = 1;
      for (int d = 0; d < patch.param_dim(); ++d)
        if (d != side.dir) n *= s * patch.knots(d).num_elements() + 1;
      total += n;
    }
    return total;
  };
  const double budget = std::max(points_per_control_point * control_points, small_model_points);
  int s = std::max(1, most);
  while (s > 1 && points(s) > budget) --s;
  return s;
}

}  // namespace isospring::io
