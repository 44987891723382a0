#pragma once
// Random NURBS patches for property tests: random degrees, interior knots (with multiplicities),
// control points and weights, from a seeded generator so failures are reproducible.
#include <random>
#include <vector>

#include "isospring/nurbs/patch.hpp"

namespace isospring::testing {

inline nurbs::KnotVector random_knots(std::mt19937& rng, int degree, int interior) {
  std::uniform_real_distribution<double> unit(0.05, 0.95);
  std::vector<double> inner;
  while (static_cast<int>(inner.size()) < interior) {
    const double t = unit(rng);
    // Occasionally repeat a knot (multiplicity up to the degree) to exercise reduced continuity.
    const int repeat = std::min(degree, 1 + static_cast<int>(rng() % 2));
    for (int r = 0; r < repeat && static_cast<int>(inner.size()) < interior; ++r)
      inner.push_back(t);
  }
  std::sort(inner.begin(), inner.end());
  std::vector<double> knots(static_cast<size_t>(degree + 1), 0.0);
  knots.insert(knots.end(), inner.begin(), inner.end());
  knots.insert(knots.end(), static_cast<size_t>(degree + 1), 1.0);
  return nurbs::KnotVector(degree, knots);
}

inline nurbs::Patch random_patch(std::mt19937& rng, int param_dim, int max_degree, bool rational,
                                 int max_interior = 3) {
  std::vector<nurbs::KnotVector> knots;
  size_t count = 1;
  for (int d = 0; d < param_dim; ++d) {
    const int degree = 1 + static_cast<int>(rng() % static_cast<unsigned>(max_degree));
    const int interior = static_cast<int>(rng() % static_cast<unsigned>(max_interior + 1));
    knots.push_back(random_knots(rng, degree, interior));
    count *= static_cast<size_t>(knots.back().num_basis());
  }
  std::uniform_real_distribution<double> coordinate(-1.0, 1.0), weight(0.3, 2.0);
  std::vector<Eigen::Vector3d> points(count);
  std::vector<double> weights(count, 1.0);
  for (size_t i = 0; i < count; ++i) {
    points[i] = Eigen::Vector3d(coordinate(rng), coordinate(rng), coordinate(rng));
    if (rational) weights[i] = weight(rng);
  }
  return nurbs::Patch(knots, points, weights);
}

inline nurbs::Param random_param(std::mt19937& rng, const nurbs::Patch& patch) {
  nurbs::Param u{0, 0, 0};
  for (int d = 0; d < patch.param_dim(); ++d) {
    std::uniform_real_distribution<double> dist(patch.param_min(d), patch.param_max(d));
    u[d] = dist(rng);
  }
  return u;
}

}  // namespace isospring::testing
