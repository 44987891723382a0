#pragma once
// Geometries and helpers shared by the analysis verification tests (benchmarks.md).
#include <Eigen/Dense>
#include <array>
#include <cmath>
#include <vector>

#include "isospring/analysis/problem.hpp"
#include "isospring/nurbs/refine.hpp"

namespace isospring::testing {

inline const double kSqrtHalf = std::sqrt(0.5);

/// Kirsch quarter plate (benchmarks.md): hole radius 1, half-width 4, upper-left quadrant,
/// degrees (2, 2), 12 control points.
inline nurbs::Patch kirsch_plate() {
  const double s = std::sqrt(2.0) - 1.0;  // 0.414213562373095
  const double w = (1.0 + kSqrtHalf) / 2.0;
  std::vector<Eigen::Vector3d> points = {
      {-1, 0, 0},   {-1, s, 0},      {-s, 1, 0},      {0, 1, 0},    // r = 1
      {-2.5, 0, 0}, {-2.5, 0.75, 0}, {-0.75, 2.5, 0}, {0, 2.5, 0},  // middle
      {-4, 0, 0},   {-4, 4, 0},      {-4, 4, 0},      {0, 4, 0}};   // outer
  std::vector<double> weights = {1, w, w, 1, 1, 1, 1, 1, 1, 1, 1, 1};
  return nurbs::Patch(
      {nurbs::KnotVector(2, {0, 0, 0, 0.5, 1, 1, 1}), nurbs::KnotVector(2, {0, 0, 0, 1, 1, 1})},
      points, weights);
}

/// Lame quarter ring Ri = 1, Ro = 2: degrees (1, 2), u radial, v circumferential.
/// `weight` is the middle weight (benchmarks.md prints 0.7071068; the exact arc needs sqrt(1/2)).
inline nurbs::Patch quarter_ring(double inner = 1.0, double outer = 2.0,
                                 double weight = kSqrtHalf) {
  std::vector<Eigen::Vector3d> points = {{inner, 0, 0},     {outer, 0, 0}, {inner, inner, 0},
                                         {outer, outer, 0}, {0, inner, 0}, {0, outer, 0}};
  return nurbs::Patch(
      {nurbs::KnotVector(1, {0, 0, 1, 1}), nurbs::KnotVector(2, {0, 0, 0, 1, 1, 1})}, points,
      {1, 1, weight, weight, 1, 1});
}

/// Octant of a thick sphere Ri..Ro: u along the equator from +x to +y, v from the equator to
/// the pole (+z, collapsed), w radial. Degrees (2, 2, 1); exact (tensor product of two arcs).
inline nurbs::Patch sphere_octant(double inner, double outer) {
  const Eigen::Vector2d circle[3] = {{1, 0}, {1, 1}, {0, 1}};
  const double arc_weight[3] = {1, kSqrtHalf, 1};
  // Meridian arc in the (radius in xy, z) plane.
  const Eigen::Vector2d meridian[3] = {{1, 0}, {1, 1}, {0, 1}};
  std::vector<Eigen::Vector3d> points;
  std::vector<double> weights;
  for (int k = 0; k < 2; ++k) {
    const double r = k == 0 ? inner : outer;
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) {
        points.emplace_back(r * meridian[j].x() * circle[i].x(),
                            r * meridian[j].x() * circle[i].y(), r * meridian[j].y());
        weights.push_back(arc_weight[i] * arc_weight[j]);
      }
  }
  const nurbs::KnotVector quadratic(2, {0, 0, 0, 1, 1, 1});
  return nurbs::Patch({quadratic, quadratic, nurbs::KnotVector(1, {0, 0, 1, 1})}, points, weights);
}

/// Rectangle [0, length] x [-depth/2, depth/2] of degree p with the given elements.
inline nurbs::Patch beam(double length, double depth, int degree, int nx, int ny) {
  nurbs::Patch bilinear(
      {nurbs::KnotVector(1, {0, 0, 1, 1}), nurbs::KnotVector(1, {0, 0, 1, 1})},
      {{0, -depth / 2, 0}, {length, -depth / 2, 0}, {0, depth / 2, 0}, {length, depth / 2, 0}});
  nurbs::Patch p = nurbs::elevate_degree(bilinear, degree - 1);
  p = nurbs::refine_uniform(p, 0, nx);
  return nurbs::refine_uniform(p, 1, ny);
}

/// Interior knots that split [0, 1] into `elements` spans graded by g(s) = s (1 + c s) / (1 + c).
/// g is a fixed smooth diffeomorphism of [0, 1] (g' runs from 1 / (1 + c) at s = 0 to
/// (1 + 2c) / (1 + c) at s = 1), so the meshes stay quasi-uniform, halving nests them (the knots
/// of n elements are among those of 2n) and the asymptotic rates in h = 1 / elements are those of
/// uniform refinement; only the constants change: elements near s = 0 are 1 + 2c times smaller
/// than those near s = 1.
inline std::vector<double> graded_knots(int elements, double c) {
  std::vector<double> knots;
  for (int i = 1; i < elements; ++i) {
    const double s = static_cast<double>(i) / elements;
    knots.push_back(s * (1 + c * s) / (1 + c));
  }
  return knots;
}

/// k-refinement with one graded direction: elevates every direction to degree[d], splits the
/// spans of the other directions uniformly into splits[d] and the graded direction (a single
/// span [0, 1]) into splits[graded] spans at graded_knots(splits[graded], c).
inline nurbs::Patch graded_k_refine(const nurbs::Patch& coarse, const std::array<int, 3>& degree,
                                    const std::array<int, 3>& splits, int graded, double c) {
  nurbs::Patch patch = coarse;
  for (int d = 0; d < patch.param_dim(); ++d) {
    const size_t i = static_cast<size_t>(d);
    patch = nurbs::elevate_degree(patch, d, degree[i] - patch.degree(d));
    if (d != graded) patch = nurbs::refine_uniform(patch, d, splits[i]);
  }
  const std::vector<double> knots = graded_knots(splits[static_cast<size_t>(graded)], c);
  return knots.empty() ? patch : nurbs::refine_knots(patch, graded, knots);
}

/// Least-squares slope of log(error) against log(h) over the last `count` levels.
inline double fitted_rate(const std::vector<double>& h, const std::vector<double>& error,
                          size_t count) {
  const size_t first = h.size() - count;
  Eigen::MatrixXd a(static_cast<Eigen::Index>(count), 2);
  Eigen::VectorXd b(static_cast<Eigen::Index>(count));
  for (size_t i = 0; i < count; ++i) {
    a(static_cast<Eigen::Index>(i), 0) = std::log(h[first + i]);
    a(static_cast<Eigen::Index>(i), 1) = 1.0;
    b[static_cast<Eigen::Index>(i)] = std::log(error[first + i]);
  }
  return a.colPivHouseholderQr().solve(b)[0];
}

/// Polar stress tensor -> Cartesian 3x3 (in-plane).
inline Eigen::Matrix3d polar_to_cartesian(double srr, double stt, double szz, double theta) {
  const double c = std::cos(theta), s = std::sin(theta);
  Eigen::Matrix3d out = Eigen::Matrix3d::Zero();
  out(0, 0) = srr * c * c + stt * s * s;
  out(1, 1) = srr * s * s + stt * c * c;
  out(0, 1) = out(1, 0) = (srr - stt) * s * c;
  out(2, 2) = szz;
  return out;
}

}  // namespace isospring::testing
