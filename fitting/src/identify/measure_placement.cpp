// Marker placement: the closest point of the model to every marker. Surfaces and volumes go
// through geometry::PointLocator (CGAL trees of the patches' tessellations and interior samples
// give each marker a start near its closest point, then one Newton inversion): 45-100 x faster
// than inverting on every patch from a sampled start on plates with 10^3-10^4 markers, 170 x on a
// volume (bench/bench_placement.cpp). Curves keep the inversion on every patch.
#include <map>

#include "isospring/fitting/measure.hpp"
#include "isospring/geometry/point_locator.hpp"
#include "isospring/nurbs/point_inversion.hpp"

namespace isospring::fitting {

namespace {

MarkerPlacement closest_point(const std::vector<nurbs::Patch>& patches, const Eigen::Vector3d& x) {
  MarkerPlacement best;
  best.distance = std::numeric_limits<double>::infinity();
  for (size_t p = 0; p < patches.size(); ++p) {
    // A patch whose control box (which contains it) is farther than the best distance so far
    // cannot hold a closer point: skip the Newton iteration.
    const auto [lo, hi] = patches[p].control_bounds();
    const Eigen::Vector3d gap = (lo - x).cwiseMax(x - hi).cwiseMax(0.0);
    if (gap.norm() > best.distance) continue;
    const nurbs::Inversion inv = nurbs::invert_point(patches[p], x);
    if (inv.distance < best.distance) {
      best.patch = static_cast<int>(p);
      best.param = inv.param;
      best.distance = inv.distance;
    }
  }
  return best;
}

}  // namespace

PlacementResult place_markers(const std::vector<nurbs::Patch>& patches,
                              const std::vector<Marker>& markers, double tolerance) {
  PlacementResult result;
  result.placements.reserve(markers.size());
  if (markers.empty()) return result;
  bool curves = patches.empty();
  for (const auto& patch : patches) curves = curves || patch.param_dim() < 2;
  const std::unique_ptr<const geometry::PointLocator> locator =
      curves ? nullptr : std::make_unique<const geometry::PointLocator>(patches);
  // Load cases usually share marker positions: place each distinct position once.
  std::map<std::array<double, 3>, MarkerPlacement> cache;
  for (size_t m = 0; m < markers.size(); ++m) {
    const Eigen::Vector3d& x = markers[m].position;
    const std::array<double, 3> key{x.x(), x.y(), x.z()};
    auto it = cache.find(key);
    if (it == cache.end()) {
      MarkerPlacement placement;
      if (locator) {
        const geometry::Location location = locator->locate(x);
        placement.patch = location.patch;
        placement.param = location.param;
        placement.distance = location.distance;
      } else {
        placement = closest_point(patches, x);
      }
      it = cache.emplace(key, placement).first;
    }
    result.placements.push_back(it->second);
    if (!(it->second.distance <= tolerance)) result.outside.push_back(static_cast<int>(m));
  }
  return result;
}

}  // namespace isospring::fitting
