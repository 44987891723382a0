// A solid with internal voids (STEP's BREP_WITH_VOIDS: an outer shell and inner shells oriented
// into the material): the CAx-IF test model bv1 (tests/data/parts/caxif_bv1.stp), a 100 mm cube
// with two box-shaped cavities, [80, 90] x [80, 90] x [10, 40] mm and [10, 30] x [20, 60] x
// [60, 80] mm. Its volume, area and centroid have closed forms (the cube less the two boxes),
// against which the reader (shells, OpenCascade's measures) and the immersed quadrature are held,
// on a grid whose planes meet none of the cavities' faces (every cavity face cuts cells) and on
// one whose planes carry them all. The boundary points on the cavities' faces must have normals
// pointing into the cavity (out of the material), and no cell's quadrature point may lie in a
// cavity. Every face is planar, so the quadrature is exact up to round-off (1.5e-13 of the volume,
// 1.7e-13 of the size for the centroid were measured); the tolerance is 1e-11.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <array>
#include <filesystem>
#include <string>

#include "isospring/geometry/cad.hpp"
#include "isospring/geometry/immersed_cad.hpp"

namespace isospring::geometry {
namespace {

namespace fs = std::filesystem;

const fs::path kFile = fs::path(ISOSPRING_SOURCE_DIR) / "tests/data/parts/caxif_bv1.stp";

struct Box {
  Eigen::Vector3d lo, hi;  // m
  double volume() const { return (hi - lo).prod(); }
  double area() const {
    const Eigen::Vector3d d = hi - lo;
    return 2 * (d.x() * d.y() + d.y() * d.z() + d.z() * d.x());
  }
  Eigen::Vector3d centre() const { return (lo + hi) / 2; }
  // Strictly inside, by more than `margin`.
  bool holds(const Eigen::Vector3d& p, double margin) const {
    return ((p - lo).array() > margin).all() && ((hi - p).array() > margin).all();
  }
  // On the closed box's boundary (within `tolerance`).
  bool on_boundary(const Eigen::Vector3d& p, double tolerance) const {
    return ((p - lo).array() > -tolerance).all() && ((hi - p).array() > -tolerance).all() &&
           !holds(p, tolerance);
  }
};

const Box kCube{Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.1, 0.1, 0.1)};
const std::array<Box, 2> kVoids{
    Box{Eigen::Vector3d(0.08, 0.08, 0.01), Eigen::Vector3d(0.09, 0.09, 0.04)},
    Box{Eigen::Vector3d(0.01, 0.02, 0.06), Eigen::Vector3d(0.03, 0.06, 0.08)}};

SolidMeasures closed_form() {
  SolidMeasures m;
  m.volume = kCube.volume();
  m.area = kCube.area();
  Eigen::Vector3d moment = kCube.volume() * kCube.centre();
  for (const Box& v : kVoids) {
    m.volume -= v.volume();
    m.area += v.area();
    moment -= v.volume() * v.centre();
  }
  m.centroid = moment / m.volume;
  return m;
}

void expect_measures(const SolidMeasures& got, const SolidMeasures& exact, double tolerance,
                     const std::string& what) {
  EXPECT_NEAR(got.volume / exact.volume, 1.0, tolerance) << what;
  EXPECT_NEAR(got.area / exact.area, 1.0, tolerance) << what;
  EXPECT_LT((got.centroid - exact.centroid).norm() / 0.1, tolerance) << what;
}

// The immersed domain on a grid of `cells` per direction: measures to `tolerance` of the closed
// form, void normals out of the material, no volume point in a void.
void check_immersion(int cells, double tolerance) {
  const CadSolid solid = read_cad_solid(kFile);
  ImmersionOptions options;
  options.cells = Eigen::Vector3i::Constant(cells);
  options.threads = 1;
  const ImmersedDomain domain = immerse_solid(solid, options);
  const std::string what = std::to_string(cells) + " cells per direction";
  expect_measures(measure_quadrature(domain), closed_form(), tolerance, what);

  int in_void = 0;
  for (const ImmersedCell& cell : domain.cells)
    for (const Eigen::Vector3d& p : cell.points)
      for (const Box& v : kVoids) in_void += v.holds(p, 1e-9) ? 1 : 0;
  EXPECT_EQ(in_void, 0) << what;

  // Each cavity's boundary: its area, its normals pointing into the cavity (away from the
  // material), and int n dA = 0 (a closed shell).
  for (const Box& v : kVoids) {
    double area = 0;
    int wrong_way = 0;
    Eigen::Vector3d flux = Eigen::Vector3d::Zero();
    for (const BoundaryPoint& b : domain.boundary) {
      if (!v.on_boundary(b.point, 1e-9)) continue;
      area += b.weight;
      flux += b.weight * b.normal;
      wrong_way += b.normal.dot(v.centre() - b.point) > 0 ? 0 : 1;
    }
    EXPECT_NEAR(area / v.area(), 1.0, tolerance) << what;
    EXPECT_EQ(wrong_way, 0) << what;
    EXPECT_LT(flux.norm() / v.area(), tolerance) << what;
  }
}

TEST(ImmersedVoids, ReaderKeepsTheInnerShells) {
  const CadModel model = read_cad(kFile);
  EXPECT_EQ(model.solids, 1);
  EXPECT_EQ(model.shells, 3);
  EXPECT_EQ(model.faces, 18);
  const SolidMeasures exact = closed_form();
  EXPECT_NEAR(model.volume / exact.volume, 1.0, 1e-12);
  // OpenCascade's measures of the solid read for immersion.
  expect_measures(measure_solid(read_cad_solid(kFile)), exact, 1e-12, "OpenCascade");
}

// 7 cells of 14.3 mm: every cavity face (at multiples of 10 mm) cuts cells.
TEST(ImmersedVoids, CutCellsIntegrateTheCavities) {
  check_immersion(7, 1e-11);
}

// 10 cells of 10 mm: every cavity face lies on a grid plane; the cavities are whole cells left
// out.
TEST(ImmersedVoids, CavitiesOnGridPlanes) {
  check_immersion(10, 1e-11);
}

}  // namespace
}  // namespace isospring::geometry
