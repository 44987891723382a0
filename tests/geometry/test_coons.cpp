// Exact NURBS Coons patches: boundary interpolation, reproduction of ruled and bilinear surfaces
// (identities of the Coons operator), compatibility, and the error cases.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include "isospring/geometry/cad.hpp"
#include "isospring/geometry/construction.hpp"
#include "isospring/geometry/coons.hpp"
#include "isospring/nurbs/refine.hpp"

namespace isospring::geometry {
namespace {

using nurbs::KnotVector;
using nurbs::Patch;

Patch line(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return Patch({KnotVector(1, {0, 0, 1, 1})}, {a, b});
}

// Point of a curve at the fraction t of its parameter range.
Eigen::Vector3d at(const Patch& c, double t) {
  return c.point({c.param_min(0) + t * (c.param_max(0) - c.param_min(0)), 0, 0});
}

TEST(Coons, CompatibleCurvesKeepTheirGeometry) {
  // A quarter arc (rational, degree 2, knots in [0, 1]) and a cubic over [2, 5] with two
  // interior knots: after compatibility both are degree 3 over [0, 1] with the same knots.
  const Patch arc = circular_arc({0, 0, 0}, 1.0, 0.0, M_PI);
  const Patch cubic({KnotVector(3, {2, 2, 2, 2, 3, 4.5, 5, 5, 5, 5})},
                    {{0, 0, 1}, {1, 2, 1}, {2, -1, 1}, {3, 0, 2}, {4, 1, 1}, {5, 0, 1}});
  const auto pair = make_compatible({arc, cubic});
  ASSERT_EQ(pair.size(), 2u);
  EXPECT_EQ(pair[0].knots(0).values(), pair[1].knots(0).values());
  EXPECT_EQ(pair[0].degree(0), 3);
  EXPECT_EQ(pair[0].param_min(0), 0.0);
  EXPECT_EQ(pair[0].param_max(0), 1.0);
  for (int n = 0; n <= 20; ++n) {  // exact refinement: round-off only
    const double t = n / 20.0;
    EXPECT_LT((at(pair[0], t) - at(arc, t)).norm(), 1e-14);
    EXPECT_LT((at(pair[1], t) - at(cubic, t)).norm(), 1e-14);
  }
}

TEST(Coons, InterpolatesItsFourBoundaryCurves) {
  // Mixed boundary: a rational half circle, a cubic, and two curved quadratics; all different
  // knots and parameter ranges.
  const Patch bottom = circular_arc({1, 0, 0}, 1.0, M_PI, -M_PI);  // (0,0,0) -> (2,0,0)
  const Patch right({KnotVector(2, {0, 0, 0, 1, 1, 1})}, {{2, 0, 0}, {2.5, 1, 0.3}, {2, 2, 0}});
  const Patch top({KnotVector(3, {1, 1, 1, 1, 1.5, 3, 3, 3, 3})},
                  {{0, 2, 0.2}, {0.5, 2.4, 0}, {1, 2.2, 0.5}, {1.6, 1.8, 0}, {2, 2, 0}});
  const Patch left({KnotVector(2, {0, 0, 0, 0.3, 1, 1, 1})},
                   {{0, 0, 0}, {-0.3, 0.5, 0}, {-0.2, 1.5, 0.1}, {0, 2, 0.2}});
  const Patch s = coons_patch(bottom, right, top, left);
  EXPECT_TRUE(s.is_rational());
  for (int n = 0; n <= 40; ++n) {  // the boundary rows are the curves' control points: round-off
    const double t = n / 40.0;
    EXPECT_LT((s.point({t, 0, 0}) - at(bottom, t)).norm(), 1e-14);
    EXPECT_LT((s.point({t, 1, 0}) - at(top, t)).norm(), 1e-14);
    EXPECT_LT((s.point({0, t, 0}) - at(left, t)).norm(), 1e-14);
    EXPECT_LT((s.point({1, t, 0}) - at(right, t)).norm(), 1e-14);
  }
}

TEST(Coons, ReproducesRuledAndBilinearSurfaces) {
  // Coons of the boundary of a ruled surface (two curves with the same weights, joined by lines)
  // is that ruled surface: here a piece of a cone between a quarter circle of radius 1 at z = 0
  // and one of radius 2 at z = 1.
  const Patch low = circular_arc({0, 0, 0}, 1.0, 0.0, M_PI / 2);
  const Patch high = circular_arc({0, 0, 1}, 2.0, 0.0, M_PI / 2);
  const Patch cone = ruled(low, high);
  const Patch s =
      coons_patch(low, line(at(low, 1), at(high, 1)), high, line(at(low, 0), at(high, 0)));
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(0, 1);
  for (int n = 0; n < 50; ++n) {
    const nurbs::Param u{unit(rng), unit(rng), 0};
    EXPECT_LT((s.point(u) - cone.point(u)).norm(), 1e-14);
    const Eigen::Vector3d x = s.point(u);  // on the cone r = 1 + z
    EXPECT_NEAR(std::hypot(x.x(), x.y()), 1.0 + x.z(), 1e-14);
  }
  // Four straight sides: the bilinear patch through the corners.
  const Eigen::Vector3d a(0, 0, 0), b(2, 0, 1), c(2.5, 3, 0), d(-0.5, 2, 2);
  const Patch q = coons_patch(line(a, b), line(b, c), line(d, c), line(a, d));
  for (int n = 0; n < 20; ++n) {
    const double u = unit(rng), v = unit(rng);
    const Eigen::Vector3d bilinear =
        (1 - u) * (1 - v) * a + u * (1 - v) * b + u * v * c + (1 - u) * v * d;
    EXPECT_LT((q.point({u, v, 0}) - bilinear).norm(), 1e-14);
  }
}

TEST(Coons, RejectsOpenLoopsAndMismatchedWeights) {
  const Eigen::Vector3d a(0, 0, 0), b(1, 0, 0), c(1, 1, 0), d(0, 1, 0);
  EXPECT_THROW(
      coons_patch(line(a, b), line(b, c), line(d, c), line(a + Eigen::Vector3d(0, 0, 1e-6), d)),
      std::invalid_argument);
  // Within the corner tolerance the corners are merged.
  EXPECT_NO_THROW(
      coons_patch(line(a, b), line(b, c), line(d, c), line(a + Eigen::Vector3d(0, 0, 1e-10), d)));
  // End weights 1 and 2 on one side only: no constant scaling matches all four corners.
  const Patch skewed({KnotVector(1, {0, 0, 1, 1})}, {b, c}, {1.0, 2.0});
  EXPECT_THROW(coons_patch(line(a, b), skewed, line(d, c), line(a, d)), std::invalid_argument);
  // Scaled weights of a whole curve are the same curve: accepted.
  const Patch scaled({KnotVector(1, {0, 0, 1, 1})}, {b, c}, {3.0, 3.0});
  EXPECT_NO_THROW(coons_patch(line(a, b), scaled, line(d, c), line(a, d)));
}

// The six boundary faces of a volume patch in coons_volume's order (u0, u1, v0, v1, w0, w1).
std::array<Patch, 6> faces_of(const Patch& volume) {
  std::array<Patch, 6> faces;
  for (int dir = 0; dir < 3; ++dir)
    for (int end = 0; end < 2; ++end)
      faces[static_cast<size_t>(2 * dir + end)] = boundary_side(volume, dir, end);
  return faces;
}

TEST(CoonsVolume, ReproducesAVolumeLinearInOneDirection) {
  // A rational volume ruled (linear in w) between a curved Coons surface and an affine image of
  // it: in the range of the w-blend, so the Boolean sum reproduces it exactly.
  const Patch bottom = circular_arc({1, 0, 0}, 1.0, M_PI, -M_PI);
  const Patch right({KnotVector(2, {0, 0, 0, 1, 1, 1})}, {{2, 0, 0}, {2.5, 1, 0.3}, {2, 2, 0}});
  const Patch top = line({0, 2, 0.2}, {2, 2, 0});
  const Patch left({KnotVector(2, {0, 0, 0, 0.3, 1, 1, 1})},
                   {{0, 0, 0}, {-0.3, 0.5, 0}, {-0.2, 1.5, 0.1}, {0, 2, 0.2}});
  const Patch base = coons_patch(bottom, right, top, left);
  Eigen::Matrix3d A;
  A << 1.1, 0.2, 0.0, -0.1, 0.9, 0.1, 0.0, 0.1, 1.2;
  const Patch volume = ruled(base, transformed(base, A, {0.1, -0.2, 1.5}));
  const Patch v = coons_volume(faces_of(volume));
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(0, 1);
  for (int n = 0; n < 50; ++n) {
    const nurbs::Param u{unit(rng), unit(rng), unit(rng)};
    EXPECT_LT((v.point(u) - volume.point(u)).norm(), 1e-13);
  }
}

TEST(CoonsVolume, InterpolatesItsSixFaces) {
  // A quadratic volume with perturbed control points (not reproduced inside): its faces are.
  const KnotVector k(2, {0, 0, 0, 0.4, 1, 1, 1});
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> jitter(-0.15, 0.15);
  std::vector<Eigen::Vector3d> points;
  for (int c = 0; c < 4; ++c)
    for (int b = 0; b < 4; ++b)
      for (int a = 0; a < 4; ++a)
        points.emplace_back(a + jitter(rng), b + jitter(rng), c + jitter(rng));
  const Patch volume({k, k, k}, points);
  const Patch v = coons_volume(faces_of(volume));
  std::uniform_real_distribution<double> unit(0, 1);
  double inside = 0.0;
  for (int n = 0; n < 30; ++n) {
    const double s = unit(rng), t = unit(rng);
    for (int end = 0; end < 2; ++end) {
      const double e = end;
      for (const nurbs::Param& u :
           {nurbs::Param{e, s, t}, nurbs::Param{s, e, t}, nurbs::Param{s, t, e}})
        EXPECT_LT((v.point(u) - volume.point(u)).norm(), 1e-13);
    }
    const nurbs::Param u{unit(rng), unit(rng), unit(rng)};
    inside = std::max(inside, (v.point(u) - volume.point(u)).norm());
  }
  EXPECT_GT(inside, 1e-3);  // a different volume inside: the faces are what is interpolated
  // Faces that do not share an edge are rejected.
  std::array<Patch, 6> faces = faces_of(volume);
  faces[0] = transformed(faces[0], Eigen::Matrix3d::Identity(), {0, 0, 1e-6});
  EXPECT_THROW(coons_volume(faces), std::invalid_argument);
}

}  // namespace
}  // namespace isospring::geometry
