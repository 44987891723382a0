// The immersed quadrature of every shipped and shared part on coarse grids and with the part
// moved by fractions of a cell (faces on grid planes, faces a sliver away from them, generic cuts):
// volume, centroid (cells) and area (boundary points) against OpenCascade's BRepGProp, to 1e-6
// (1e-5 for the shells that do not close, see test_immersed_every_part.cpp), on every grid. Before
// cut cells were split where their middle lines' crossings change in number, a hole whose extreme
// point lay just short of a break was missed by both Gauss orders, and closed parts missed by up to
// 7e-5 on 6 x 6 x 6 and 7 x 7 x 7 grids. Per cell, two such cases are checked against
// OpenCascade's volume of the cell's common part with the solid (BRepAlgoAPI_Common, used here as
// the independent reference only).
#include <gtest/gtest.h>

#include <BRepAlgoAPI_Common.hxx>
#include <BRepBndLib.hxx>
#include <BRepGProp.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <Bnd_Box.hxx>
#include <GProp_GProps.hxx>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <string>
#include <vector>

#include "../../geometry/src/cad_solid_shape.hpp"
#include "../common/cad_parts.hpp"
#include "isospring/geometry/immersed_cad.hpp"
#include "isospring/nurbs/error.hpp"

namespace fs = std::filesystem;

namespace isospring::geometry {
namespace {

using test::cad_files;
using test::solids_of;

// n cells per side over the part's bounding box, the part moved by `shift` cells relative to the
// grid (then n + 1 cells cover it). shift 0: the part's extreme faces lie on the grid's boundary.
struct Grid {
  int cells = 6;
  Eigen::Vector3d shift = Eigen::Vector3d::Zero();
};

ImmersionOptions grid_options(const CadSolid& solid, const Grid& g) {
  ImmersionOptions o;
  o.threads = 1;
  o.cells = Eigen::Vector3i::Constant(g.cells);
  if (g.shift.isZero()) return o;
  Bnd_Box box;
  BRepBndLib::AddOptimal(solid.shape().solid, box, false, false);
  double x0, y0, z0, x1, y1, z1;
  box.Get(x0, y0, z0, x1, y1, z1);
  const Eigen::Vector3d lo(x0, y0, z0), h = (Eigen::Vector3d(x1, y1, z1) - lo) / g.cells;
  o.box_min = lo - g.shift.cwiseProduct(h);
  o.box_max = o.box_min + (g.cells + 1) * h;
  o.cells = Eigen::Vector3i::Constant(g.cells + 1);
  return o;
}

const std::vector<Grid>& sweep() {
  // The last: a generic placement, where the rounded bracket's fillet met its plane (a tangent
  // edge) between Gauss abscissae.
  static const std::vector<Grid> grids = {{6, {0, 0, 0}},
                                          {7, {0, 0, 0}},
                                          {6, {0.5, 0.5, 0.5}},
                                          {7, {1e-3, 1e-3, 1e-3}},
                                          {5, {0.37, 0.61, 0.23}}};
  return grids;
}

void check_solid(const CadSolid& solid, const std::string& label, double& cpu) {
  const SolidMeasures m = measure_solid(solid);
  for (const Grid& g : sweep()) {
    const std::clock_t start = std::clock();
    const ImmersedDomain domain = immerse_solid(solid, grid_options(solid, g));
    cpu += static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
    const SolidMeasures q = measure_quadrature(domain);
    Eigen::Vector3d gap = Eigen::Vector3d::Zero();
    for (const BoundaryPoint& b : domain.boundary) gap += b.weight * b.normal;
    const double tolerance = gap.norm() / m.area < 1e-7 ? 1e-6 : 1e-5;
    const double volume = std::abs(q.volume / m.volume - 1.0);
    const double area = std::abs(q.area / m.area - 1.0);
    const double centroid = (q.centroid - m.centroid).norm() / std::cbrt(m.volume);
    std::printf(
        "[coarse] %s, %d cells, shift (%.3g, %.3g, %.3g): volume %.2e, area %.2e, "
        "centroid %.2e (tolerance %.0e)\n",
        label.c_str(), g.cells, g.shift.x(), g.shift.y(), g.shift.z(), volume, area, centroid,
        tolerance);
    const std::string where = label + " on " + std::to_string(g.cells) + " cells";
    EXPECT_LT(volume, tolerance) << where;
    EXPECT_LT(area, 1e-6) << where;
    EXPECT_LT(centroid, tolerance) << where;
  }
}

void check_folder(const fs::path& dir, int& checked, double& cpu) {
  for (const fs::path& file : cad_files(dir)) {
    const std::vector<CadSolid> solids = solids_of(file);
    for (size_t body = 0; body < solids.size(); ++body) {
      check_solid(solids[body],
                  fs::relative(file, dir.parent_path()).string() +
                      (solids.size() > 1 ? ", solid " + std::to_string(body) : ""),
                  cpu);
      ++checked;
    }
  }
}

// On demand (--gtest_also_run_disabled_tests): 430 s of CPU (the shared parts, below, 351 s),
// more than CI should spend on it beside the every-part test; every shipped solid passes on every
// grid. The bolt, gmsh's machined part, OCCT's screw and the
// rounded bracket used to miss on some grids (docs/immersed.md, "Coarse grids"; the cells are
// checked by test_immersed_cell_features.cpp).
TEST(ImmersedCoarseGrids, DISABLED_EveryShippedPart) {
  const fs::path source(ISOSPRING_SOURCE_DIR);
  int checked = 0;
  double cpu = 0.0;
  for (const char* dir : {"examples/cad", "examples/immersed", "tests/data/parts"})
    check_folder(source / dir, checked, cpu);
  std::printf("[coarse] %d shipped solids, %zu grids each: %.1f s CPU\n", checked, sweep().size(),
              cpu);
  EXPECT_GE(checked, 14);
}

TEST(ImmersedCoarseGrids, EverySharedPart) {
  const fs::path dir = fs::path(ISOSPRING_SHARED_DIR) / "cad";
  if (!fs::exists(dir))
    GTEST_SKIP() << "the third-party parts of ../shared/cad are not present (" << dir << ")";
  int checked = 0;
  double cpu = 0.0;
  check_folder(dir, checked, cpu);
  std::printf("[coarse] %d shared solids, %zu grids each: %.1f s CPU\n", checked, sweep().size(),
              cpu);
  EXPECT_GE(checked, 6);
}

// The largest error of a cell's volume against OpenCascade's volume of the cell's box in common
// with the solid (BRepAlgoAPI_Common: the independent reference, here only), relative to the cell.
double worst_cell(const CadSolid& solid, const Grid& g) {
  const ImmersedDomain d = immerse_solid(solid, grid_options(solid, g));
  const int p = d.background.degree(0);
  Eigen::Vector3d h;
  for (int k = 0; k < 3; ++k) h[k] = d.extent[k] / (d.background.knots(k).num_basis() - p);
  double worst = 0.0;
  for (const ImmersedCell& cell : d.cells) {
    if (cell.kind != CellKind::kCut) continue;
    const Eigen::Vector3d lo =
        d.origin + h.cwiseProduct((cell.span - Eigen::Vector3i::Constant(p)).cast<double>());
    const Eigen::Vector3d hi = lo + h;
    double volume = 0.0;
    for (double w : cell.weights) volume += w;
    BRepPrimAPI_MakeBox box(gp_Pnt(lo.x(), lo.y(), lo.z()), gp_Pnt(hi.x(), hi.y(), hi.z()));
    GProp_GProps props;
    BRepGProp::VolumeProperties(BRepAlgoAPI_Common(box.Shape(), solid.shape().solid).Shape(), props,
                                1e-10);
    worst = std::max(worst, std::abs(volume - props.Mass()) / h.prod());
  }
  return worst;
}

// Before: the L-bracket's worst cell 2.8e-4 of its volume (6^3), the tube's 7.7e-4 (moved by 1e-3
// of a cell, its end faces a sliver from the cells' faces).
TEST(ImmersedCoarseGrids, CellsMatchTheirCommonPartWithTheSolid) {
  const double tube =
      worst_cell(read_cad_solid(fs::path(ISOSPRING_SOURCE_DIR) / "examples/cad/tube.step"),
                 {6, {1e-3, 1e-3, 1e-3}});
  std::printf("[coarse] tube, 6 cells moved by 1e-3: worst cut cell %.2e of its volume\n", tube);
  EXPECT_LT(tube, 1e-5);
  const fs::path bracket = fs::path(ISOSPRING_SHARED_DIR) / "cad" / "l_bracket_caxif.stp";
  if (!fs::exists(bracket))
    GTEST_SKIP() << "the CAx-IF L-bracket of ../shared/cad is not present (" << bracket << ")";
  const double l = worst_cell(read_cad_solid(bracket), {6, {0, 0, 0}});
  std::printf("[coarse] L-bracket, 6 cells: worst cut cell %.2e of its volume\n", l);
  EXPECT_LT(l, 1e-5);
}

}  // namespace
}  // namespace isospring::geometry
