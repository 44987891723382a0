// Marker placement: fitting::place_markers against geometry::PointLocator (CGAL AABB trees of
// the patches' tessellations, then one Newton inversion from the closest tessellation point).
//
//   plate/<elements>/<markers>: the quarter plate with a hole (2 patches, degree 3, elements per
//     direction and patch), markers on a grid over the plate (DIC-like full-field data);
//   bar/<markers>: a box 0.1 x 0.02 x 0.02 m, degree 3, 20 x 4 x 4 elements, markers inside.
//
// Both give the same placements (tests/fitting/test_measure_placement.cpp); the counters report
// the largest distance difference between them.
#include <benchmark/benchmark.h>

#include <cmath>

#include "isospring/fitting/measure.hpp"
#include "isospring/geometry/point_locator.hpp"
#include "isospring/geometry/primitives.hpp"
#include "isospring/nurbs/refine.hpp"

namespace {

using namespace isospring;

std::vector<nurbs::Patch> refined(std::vector<nurbs::Patch> patches, int degree, int elements) {
  for (auto& patch : patches)
    patch = nurbs::k_refine(patch, {degree, degree, degree}, {elements, elements, elements});
  return patches;
}

// Markers on an n x n grid over the quarter plate [-4, 0] x [0, 4] outside the hole (r > 1.05).
std::vector<fitting::Marker> plate_markers(int count) {
  const int n = static_cast<int>(std::sqrt(static_cast<double>(count) / (1.0 - M_PI / 64.0)));
  std::vector<fitting::Marker> markers;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const Eigen::Vector3d x(-4.0 + 4.0 * (i + 0.5) / n, 4.0 * (j + 0.5) / n, 0.0);
      if (x.head<2>().norm() < 1.05) continue;
      fitting::Marker m;
      m.position = x;
      m.load_case = "L1";
      markers.push_back(m);
    }
  return markers;
}

std::vector<fitting::Marker> bar_markers(int count) {
  const int n = static_cast<int>(std::cbrt(count / 4.0));
  std::vector<fitting::Marker> markers;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < 4 * n; ++i) {
        fitting::Marker m;
        m.position = {0.1 * (i + 0.5) / (4 * n), 0.02 * (j + 0.5) / n, 0.02 * (k + 0.5) / n};
        m.load_case = "L1";
        markers.push_back(m);
      }
  return markers;
}

void run(benchmark::State& state, const std::vector<nurbs::Patch>& patches,
         const std::vector<fitting::Marker>& markers, bool locator) {
  std::vector<Eigen::Vector3d> points;
  for (const auto& m : markers) points.push_back(m.position);
  double largest = 0.0;
  for (auto _ : state) {
    if (locator) {
      const geometry::PointLocator tree(patches);
      const auto batch = tree.locate_all(points, 1e-9);
      for (const auto& l : batch.locations) largest = std::max(largest, l.distance);
    } else {
      const auto placed = fitting::place_markers(patches, markers, 1e-9);
      for (const auto& p : placed.placements) largest = std::max(largest, p.distance);
    }
    benchmark::ClobberMemory();
  }
  state.counters["markers"] = static_cast<double>(markers.size());
  state.counters["largest_distance"] = largest;
}

void BM_PlacePlate(benchmark::State& state) {
  const auto patches = refined(geometry::plate_with_hole_quarter_two_patch(1.0, 4.0), 3,
                               static_cast<int>(state.range(0)));
  run(state, patches, plate_markers(static_cast<int>(state.range(1))), state.range(2) != 0);
}
BENCHMARK(BM_PlacePlate)
    ->ArgNames({"elements", "markers", "cgal"})
    ->ArgsProduct({{8, 32}, {1000, 10000}, {0, 1}})
    ->Unit(benchmark::kMillisecond);

void BM_PlaceBar(benchmark::State& state) {
  const std::vector<nurbs::Patch> bar{
      nurbs::k_refine(geometry::box(0.1, 0.02, 0.02)[0], {3, 3, 3}, {20, 4, 4})};
  run(state, bar, bar_markers(static_cast<int>(state.range(0))), state.range(1) != 0);
}
BENCHMARK(BM_PlaceBar)
    ->ArgNames({"markers", "cgal"})
    ->ArgsProduct({{500, 5000}, {0, 1}})
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
