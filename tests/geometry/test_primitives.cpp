// Exact primitives: measure against closed forms, points on exact circles/spheres/ellipses,
// right-handed parametrisations, conformity of multi-patch parts, published control points.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "isospring/geometry/construction.hpp"
#include "isospring/geometry/measure.hpp"
#include "isospring/geometry/primitives.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::geometry {
namespace {

// Relative tolerance for areas/volumes: the quadrature reaches ~1e-15; 1e-12 leaves room for
// summation round-off over many points (see MeasureRule).
constexpr double kMeasureTolerance = 1e-12;

void expect_right_handed(const Patches& patches) {
  for (size_t p = 0; p < patches.size(); ++p) {
    const JacobianRange range = jacobian_range(patches[p], 5);
    EXPECT_GT(range.min, 0.0) << "patch " << p;
  }
}

void expect_measure(const Patches& patches, double exact) {
  EXPECT_NEAR(measure(patches) / exact, 1.0, kMeasureTolerance);
}

// Random parameters on a side (dir = end) of a patch.
std::vector<nurbs::Param> random_params(const nurbs::Patch& patch, int count, int fixed_dir = -1,
                                        double fixed_value = 0.0) {
  std::mt19937 rng(7);
  std::vector<nurbs::Param> params;
  for (int n = 0; n < count; ++n) {
    nurbs::Param u{0, 0, 0};
    for (int d = 0; d < patch.param_dim(); ++d) {
      std::uniform_real_distribution<double> dist(patch.param_min(d), patch.param_max(d));
      u[static_cast<size_t>(d)] = d == fixed_dir ? fixed_value : dist(rng);
    }
    params.push_back(u);
  }
  return params;
}

TEST(Rectangle, AreaCornersAndSides) {
  const Patches r = rectangle(2.0, 0.5);
  expect_measure(r, 1.0);
  expect_right_handed(r);
  EXPECT_TRUE(r[0].point({0, 0, 0}).isApprox(Eigen::Vector3d(0, 0, 0)));
  EXPECT_TRUE(r[0].point({1, 0.5, 0}).isApprox(Eigen::Vector3d(2.0, 0.25, 0)));
  EXPECT_EQ(r[0].physical_dim(), 2);
}

TEST(Box, VolumeAndSideConvention) {
  const Patches b = box(1.0, 2.0, 3.0);
  expect_measure(b, 6.0);
  expect_right_handed(b);
  // u1 is x = size[0], v along y, w along z (case-file convention).
  EXPECT_TRUE(b[0].point({1, 0.5, 0.5}).isApprox(Eigen::Vector3d(1.0, 1.0, 1.5)));
  EXPECT_TRUE(b[0].point({0.25, 1, 0}).isApprox(Eigen::Vector3d(0.25, 2.0, 0)));
}

TEST(Disk, AreaRadiusAndJacobian) {
  const double r = 1.7;
  const Patches d = disk(r);
  expect_measure(d, M_PI * r * r);
  expect_right_handed(d);
  for (int side = 0; side < 2; ++side)
    for (int dir = 0; dir < 2; ++dir)
      for (const auto& u : random_params(d[0], 20, dir, side))
        EXPECT_NEAR(d[0].point(u).norm(), r, 1e-14 * r);
}

TEST(Disk, FivePatchAreaRadiusAndConformity) {
  const double r = 0.8;
  const Patches d = disk_five_patch(r);
  ASSERT_EQ(d.size(), 5u);
  expect_measure(d, M_PI * r * r);
  expect_right_handed(d);
  for (size_t p = 1; p < 5; ++p)
    for (const auto& u : random_params(d[p], 20, 1, 1.0))
      EXPECT_NEAR(d[p].point(u).norm(), r, 1e-14 * r);
  // Each outer patch's inner side reproduces the square's side point by point.
  for (size_t p = 1; p < 5; ++p)
    for (const auto& u : random_params(d[p], 10, 1, 0.0)) {
      const Eigen::Vector3d x = d[p].point(u);
      EXPECT_NEAR(std::max(std::abs(x.x()), std::abs(x.y())), 0.5 * r * std::sqrt(0.5), 1e-15);
    }
}

TEST(Ellipse, AreaAndBoundary) {
  const Patches e = ellipse(2.0, 0.5);
  expect_measure(e, M_PI * 2.0 * 0.5);
  expect_right_handed(e);
  for (const auto& u : random_params(e[0], 20, 0, 1.0)) {
    const Eigen::Vector3d x = e[0].point(u);
    EXPECT_NEAR(x.x() * x.x() / 4.0 + x.y() * x.y() / 0.25, 1.0, 1e-14);
  }
}

TEST(Annulus, MatchesLameBenchmarkPatch) {
  const Patches a = annulus(1.0, 2.0);
  const nurbs::Patch& p = a[0];
  ASSERT_EQ(p.num_points(0), 2);
  ASSERT_EQ(p.num_points(1), 3);
  const std::vector<Eigen::Vector3d> expected{{1, 0, 0}, {2, 0, 0}, {1, 1, 0},
                                              {2, 2, 0}, {0, 1, 0}, {0, 2, 0}};
  for (int i = 0; i < 6; ++i) EXPECT_LT((p.control_point(i) - expected[i]).norm(), 1e-15) << i;
  EXPECT_NEAR(p.weight(2), std::sqrt(0.5), 1e-16);
  expect_measure(a, 0.75 * M_PI);
  expect_right_handed(a);
}

TEST(Annulus, FullRingAndRadii) {
  const Patches a = annulus(0.5, 1.5, 0.3, 2 * M_PI);
  expect_measure(a, M_PI * (1.5 * 1.5 - 0.25));
  expect_right_handed(a);
  for (int end = 0; end < 2; ++end)
    for (const auto& u : random_params(a[0], 20, 0, end))
      EXPECT_NEAR(a[0].point(u).norm(), end ? 1.5 : 0.5, 1e-14);
}

TEST(PlateWithHole, ReproducesBenchmarkTable) {
  const nurbs::Patch p = plate_with_hole_quarter(1.0, 4.0)[0];
  const double t = 0.414213562373095, w = 0.853553390593274;
  const std::vector<Eigen::Vector3d> expected{
      {-1, 0, 0},      {-1, t, 0},  {-t, 1, 0}, {0, 1, 0},  {-2.5, 0, 0}, {-2.5, 0.75, 0},
      {-0.75, 2.5, 0}, {0, 2.5, 0}, {-4, 0, 0}, {-4, 4, 0}, {-4, 4, 0},   {0, 4, 0}};
  const std::vector<double> weights{1, w, w, 1, 1, 1, 1, 1, 1, 1, 1, 1};
  ASSERT_EQ(p.num_points(), 12);
  for (int i = 0; i < 12; ++i) {
    EXPECT_LT((p.control_point(i) - expected[i]).norm(), 1e-14) << i;
    EXPECT_NEAR(p.weight(i), weights[i], 1e-14) << i;
  }
  EXPECT_EQ(p.knots(0).values(), (std::vector<double>{0, 0, 0, 0.5, 1, 1, 1}));
}

TEST(PlateWithHole, AreaHoleAndJacobian) {
  for (double L : {4.0, 2.0}) {
    const Patches single = plate_with_hole_quarter(1.0, L);
    const Patches two = plate_with_hole_quarter_two_patch(1.0, L);
    const double exact = L * L - M_PI / 4;
    expect_measure(single, exact);
    expect_measure(two, exact);
    expect_right_handed(single);
    expect_right_handed(two);
    for (const auto& u : random_params(single[0], 20, 1, 0.0))
      EXPECT_NEAR(single[0].point(u).norm(), 1.0, 1e-14);
    // The two patches meet at the diagonal from (-sqrt(.5), sqrt(.5)) to (-L, L).
    EXPECT_LT((two[0].point({0.5, 1, 0}) - Eigen::Vector3d(-L, L, 0)).norm(), 1e-14);
    EXPECT_LT((two[1].point({0.5, 1, 0}) - Eigen::Vector3d(-L, L, 0)).norm(), 1e-14);
    for (int v = 0; v < 3; ++v)
      EXPECT_LT(
          (two[0].control_point(two[0].index(2, v)) - two[1].control_point(two[1].index(0, v)))
              .norm(),
          1e-15);
  }
}

TEST(Tube, VolumeAndRadii) {
  const Patches t = tube_sector(1.0, 2.0, 3.0);
  expect_measure(t, 0.75 * M_PI * 3.0);
  expect_right_handed(t);
  for (const auto& u : random_params(t[0], 20, 0, 1.0)) {
    const Eigen::Vector3d x = t[0].point(u);
    EXPECT_NEAR(std::hypot(x.x(), x.y()), 2.0, 1e-14);
  }
}

TEST(Torus, VolumeSectionAndNet) {
  const double R = 0.875, r = 0.375;  // [S15]: inner radius 0.5, outer radius 1.25
  const Patches t = solid_torus(R, r);
  EXPECT_EQ(t[0].num_points(0), 9);
  EXPECT_EQ(t[0].num_points(1), 3);
  EXPECT_EQ(t[0].num_points(2), 3);
  expect_measure(t, 2 * M_PI * M_PI * R * r * r);
  expect_right_handed(t);
  for (int end = 0; end < 2; ++end)
    for (const auto& u : random_params(t[0], 20, 1, end)) {
      const Eigen::Vector3d x = t[0].point(u);
      EXPECT_NEAR(std::hypot(std::hypot(x.x(), x.y()) - R, x.z()), r, 1e-14);
    }
}

TEST(HollowSphere, VolumeRadiiAndJacobian) {
  const Patches s = hollow_sphere_sector(1.0, 2.0);
  expect_measure(s, M_PI / 2 * (8.0 - 1.0) / 3.0);
  expect_right_handed(s);
  for (int end = 0; end < 2; ++end)
    for (const auto& u : random_params(s[0], 20, 1, end))
      EXPECT_NEAR(s[0].point(u).norm(), end ? 2.0 : 1.0, 1e-14);
  // A general sector: azimuth 200 degrees, polar 120 degrees.
  const double az = 200 * M_PI / 180, polar = 120 * M_PI / 180;
  const Patches g = hollow_sphere_sector(0.5, 1.0, polar, az);
  expect_measure(g, az * (1.0 - 0.125) / 3.0 * (1.0 - std::cos(polar)));
  expect_right_handed(g);
}

TEST(Spheroid, VolumeAndSurface) {
  const double a = 2.0, b = 0.5;
  const Patches s = prolate_spheroid(a, b);
  expect_measure(s, 4.0 / 3.0 * M_PI * a * b * b);
  expect_right_handed(s);
  for (const auto& u : random_params(s[0], 20, 2, 1.0)) {
    const Eigen::Vector3d x = s[0].point(u);
    EXPECT_NEAR((x.x() * x.x() + x.y() * x.y()) / (b * b) + x.z() * x.z() / (a * a), 1.0, 1e-14);
  }
}

TEST(Spheroid, CoupledMatchesS15Net) {
  const Patches c = coupled_spheroid();
  ASSERT_EQ(c.size(), 2u);
  for (const auto& p : c) {
    EXPECT_EQ(p.num_points(0), 9);
    EXPECT_EQ(p.num_points(1), 5);
    EXPECT_EQ(p.num_points(2), 3);
    EXPECT_EQ(p.degree(0), 2);
    EXPECT_EQ(p.degree(1), 2);
    EXPECT_EQ(p.degree(2), 1);
  }
  expect_measure(c, 2 * 4.0 / 3.0 * M_PI * 1.0 * 0.25);
  expect_right_handed(c);
  EXPECT_LT((c[0].point({0, 1, 0}) - Eigen::Vector3d(0, 0, 2)).norm(), 1e-15);
  EXPECT_LT((c[1].point({0, 0, 0}) - Eigen::Vector3d(0, 0, 2)).norm(), 1e-15);
}

TEST(ThinPlate, VolumeIsAreaTimesThickness) {
  const Patches plate = thin_plate(plate_with_hole_quarter_two_patch(1.0, 4.0), 0.1);
  expect_measure(plate, (16.0 - M_PI / 4) * 0.1);
  expect_right_handed(plate);
  EXPECT_THROW(thin_plate(box(1, 1, 1), 0.1), nurbs::InputError);
}

TEST(Primitives, BadParametersAreInputErrors) {
  EXPECT_THROW(rectangle(0.0, 1.0), nurbs::InputError);
  EXPECT_THROW(box(1.0, 1.0, NAN), nurbs::InputError);
  EXPECT_THROW(disk(-1.0), nurbs::InputError);
  EXPECT_THROW(annulus(2.0, 1.0), nurbs::InputError);
  EXPECT_THROW(plate_with_hole_quarter(4.0, 4.0), nurbs::InputError);
  EXPECT_THROW(solid_torus(0.3, 0.5), nurbs::InputError);
  EXPECT_THROW(hollow_sphere_sector(1.0, 2.0, 4.0), nurbs::InputError);
}

TEST(Construction, SplitSwapAndReverseKeepGeometry) {
  const nurbs::Patch p = solid_torus(2.0, 1.0)[0];
  const auto [a, b] = split_patch(p, 0, 0.3);
  const nurbs::Patch r = reverse_direction(p, 1);
  const nurbs::Patch s = swap_directions(p, 0, 2);
  for (const auto& u : random_params(p, 30)) {
    const Eigen::Vector3d x = p.point(u);
    const nurbs::Patch& half = u[0] <= 0.3 ? a : b;
    EXPECT_LT((half.point(u) - x).norm(), 1e-14);
    EXPECT_LT((r.point({u[0], 1.0 - u[1], u[2]}) - x).norm(), 1e-14);
    EXPECT_LT((s.point({u[2], u[1], u[0]}) - x).norm(), 1e-14);
  }
}

}  // namespace
}  // namespace isospring::geometry
