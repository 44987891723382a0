// Kept grid planes (ImmersionOptions::breaks) that lie a tolerance away from the box's ends or
// from each other: they must not make sliver cells. The knots against graded_ticks' rule (an end
// within the part's tolerance moves onto the break, a break closer than kSmallestCellFraction of
// a cell is dropped), a block whose box is offset from its faces by 1e-7, 1e-9 and 0 m (the same
// cells), gmsh's machined part, whose OpenCascade box lies about 1e-7 m outside its faces, and a
// grading asking for cells below that fraction (refused).
#include <gtest/gtest.h>

#include <BRepBndLib.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <Bnd_Box.hxx>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <vector>

#include "../../geometry/src/cad_solid_shape.hpp"
#include "../../geometry/src/immersed_grading.hpp"
#include "isospring/geometry/immersed_cad.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::geometry {
namespace {

double thinnest(const std::vector<double>& t) {
  double d = t.back() - t.front();
  for (size_t i = 1; i < t.size(); ++i) d = std::min(d, t[i] - t[i - 1]);
  return d;
}

// On [0, 1] with H = 0.1: a break 1e-7 inside an end moves that end onto it when the snap
// distance allows (then the cells are 10 equal ones of the shorter box), and is dropped when it
// does not; two breaks 1e-7 apart count once; a break 1e-3 H + a little from an end is kept.
TEST(GridSlivers, BreaksNearEndsAndEachOther) {
  const std::vector<double> snapped =
      detail::graded_ticks(0.0, 1.0, 10, {}, 0, {1e-7, 1 - 1e-7}, 1e-6);
  ASSERT_EQ(snapped.size(), 11u);
  EXPECT_EQ(snapped.front(), 1e-7);
  EXPECT_EQ(snapped.back(), 1 - 1e-7);
  for (size_t i = 1; i < snapped.size(); ++i)
    EXPECT_NEAR(snapped[i] - snapped[i - 1], (1 - 2e-7) / 10, 1e-15);
  const std::vector<double> dropped =
      detail::graded_ticks(0.0, 1.0, 10, {}, 0, {1e-7, 1 - 1e-7}, 1e-8);
  ASSERT_EQ(dropped.size(), 11u);
  for (size_t i = 0; i < dropped.size(); ++i)
    EXPECT_NEAR(dropped[i], 0.1 * static_cast<double>(i), 1e-15);
  // A break just outside the box within the snap distance moves the end out onto it.
  const std::vector<double> out = detail::graded_ticks(0.0, 1.0, 10, {}, 0, {-1e-7}, 1e-6);
  EXPECT_EQ(out.front(), -1e-7);
  const std::vector<double> pair =
      detail::graded_ticks(0.0, 1.0, 10, {}, 0, {0.25, 0.25 + 1e-7, 0.25 - 1e-7}, 1e-6);
  EXPECT_EQ(
      std::count_if(pair.begin(), pair.end(), [](double x) { return std::abs(x - 0.25) < 1e-6; }),
      1);
  EXPECT_GE(thinnest(pair), (0.25 - 1e-7) / 3 - 1e-15);
  const double near = 1.5e-3 * 0.1;
  const std::vector<double> kept = detail::graded_ticks(0.0, 1.0, 10, {}, 0, {near}, 1e-6);
  EXPECT_EQ(kept[1], near);
  EXPECT_GE(thinnest(kept), detail::kSmallestCellFraction * 0.1);
  // Graded with breaks a tolerance apart: still no cell below the fraction of H.
  const std::vector<double> graded = detail::graded_ticks(0.0, 1.0, 10, {{0, 0.3, 0.005, 1.5}}, 0,
                                                          {0.3, 0.3 + 2e-7, 1 - 3e-8, 2e-8}, 1e-6);
  EXPECT_GE(thinnest(graded), detail::kSmallestCellFraction * 0.1);
}

// A 0.03 x 0.02 x 0.02 block in a user box 0.01 larger on the upper sides, its lower sides `off`
// below the block's faces (0, 1e-9, 1e-7 m), its faces kept as breaks: the box's lower ends snap
// onto the faces, so all three give the same grid (the same origin to round-off), the same inside
// and cut cells (none cut: every face on a grid plane) and the block's volume.
TEST(GridSlivers, BlockOffsetFromGridPlanesGivesTheSameCells) {
  const CadSolid block =
      detail::make_cad_solid(BRepPrimAPI_MakeBox(0.03, 0.02, 0.02).Shape(), "block");
  std::vector<ImmersionStats> stats;
  for (const double off : {0.0, 1e-9, 1e-7}) {
    ImmersionOptions o;
    o.cell_size = 0.01;
    o.box_min = Eigen::Vector3d::Constant(-off);
    o.box_max = Eigen::Vector3d(0.04, 0.03, 0.03);
    o.breaks = planar_face_coordinates(block);
    ImmersionStats s;
    const ImmersedDomain d = immerse_solid(block, o, &s);
    EXPECT_NEAR((d.origin - Eigen::Vector3d::Zero()).norm(), 0.0, 1e-15) << "off " << off;
    for (int k = 0; k < 3; ++k) {
      const std::vector<double> u = d.background.knots(k).unique();
      EXPECT_GE(thinnest(u) * d.extent[k], detail::kSmallestCellFraction * 0.01) << off;
    }
    EXPECT_NEAR(measure_quadrature(d).volume, 0.03 * 0.02 * 0.02, 1e-12 * 1.2e-5) << off;
    stats.push_back(s);
  }
  for (const ImmersionStats& s : stats) {
    EXPECT_EQ(s.inside_cells, stats[0].inside_cells);
    EXPECT_EQ(s.cut_cells, 0);
  }
  EXPECT_EQ(stats[0].inside_cells, 3 * 2 * 2);
}

// gmsh's machined part (26 faces, mm) with its planar faces kept on a coarse grid: OpenCascade's
// optimal box lies up to about 1e-7 m outside several of those faces, which under the old rule
// (breaks merged only within 1e-9 of the box) made cells that thin. Now no cell is thinner than
// kSmallestCellFraction of the base cell, every face's box lies inside the grid, and the volume
// is OpenCascade's to 1e-6.
TEST(GridSlivers, MachinedPartWithKeptPlanarFaces) {
  const std::filesystem::path file =
      std::filesystem::path(ISOSPRING_SOURCE_DIR) / "tests/data/parts/gmsh_part.step";
  const CadSolid part = read_cad_solid(file);
  const std::array<std::vector<double>, 3> breaks = planar_face_coordinates(part);
  Bnd_Box box;
  BRepBndLib::AddOptimal(part.shape().solid, box, false, false);
  double lo[3], hi[3];
  box.Get(lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
  const double cell = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]}) / 8.0;
  int old_slivers = 0;
  for (int k = 0; k < 3; ++k)
    for (double x : breaks[static_cast<size_t>(k)]) {
      const double gap = std::min(std::abs(x - lo[k]), std::abs(hi[k] - x));
      if (gap > 1e-9 * (hi[k] - lo[k]) && gap < detail::kSmallestCellFraction * cell) {
        ++old_slivers;
        std::printf("axis %d: kept plane %.9g m is %.3g m from OpenCascade's box end\n", k, x, gap);
      }
    }
  std::printf("gmsh part: %d planes would have made cells under 1e-3 of the cell (%.3g m)\n",
              old_slivers, cell);

  ImmersionOptions o;
  o.cell_size = cell;
  o.breaks = breaks;
  ImmersionStats s;
  const ImmersedDomain d = immerse_solid(part, o, &s);
  double smallest = 1.0;
  for (int k = 0; k < 3; ++k) {
    const std::vector<double> u = d.background.knots(k).unique();
    smallest = std::min(smallest, thinnest(u) * d.extent[k] / cell);
    EXPECT_LE(d.origin[k], lo[k] + 1e-6) << k;  // the snap distance, 10 confusions
    EXPECT_GE(d.origin[k] + d.extent[k], hi[k] - 1e-6) << k;
  }
  const SolidMeasures exact = measure_solid(part), ours = measure_quadrature(d);
  std::printf(
      "gmsh part: thinnest cell %.3g of the base cell; %d inside, %d cut; volume %.3g off\n",
      smallest, s.inside_cells, s.cut_cells, ours.volume / exact.volume - 1);
  EXPECT_GE(smallest, detail::kSmallestCellFraction);
  EXPECT_NEAR(ours.volume, exact.volume, 1e-6 * exact.volume);
}

TEST(GridSlivers, GradingBelowTheFractionIsRefused) {
  const CadSolid block =
      detail::make_cad_solid(BRepPrimAPI_MakeBox(0.03, 0.02, 0.02).Shape(), "block");
  ImmersionOptions o;
  o.cell_size = 0.01;
  o.grading = {{0, 0.01, 1e-6, 1.5}};
  try {
    immerse_solid(block, o);
    FAIL() << "no error";
  } catch (const nurbs::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("grading: smallest"), std::string::npos) << e.what();
  }
}

// The boundary quadrature's size is checked before it allocates: a 0.03 x 0.02 x 0.02 block on
// 0.01 cells takes 6 faces x 5 x 2^2 pieces x 16 points x sizeof(BoundaryPoint) at least, so a
// limit of 1e-6 GB (1,000 bytes) is refused, naming the option and a face, and the default passes.
TEST(GridSlivers, QuadratureSizeGuard) {
  const CadSolid block =
      detail::make_cad_solid(BRepPrimAPI_MakeBox(0.03, 0.02, 0.02).Shape(), "block");
  ImmersionOptions o;
  o.cell_size = 0.01;
  o.max_quadrature_gb = 1e-6;
  try {
    immerse_solid(block, o);
    FAIL() << "no error";
  } catch (const nurbs::InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("max_quadrature_gb"), std::string::npos) << what;
    EXPECT_NE(what.find("on face "), std::string::npos) << what;
  }
  o.max_quadrature_gb = 8.0;
  EXPECT_NO_THROW(immerse_solid(block, o));
  o.max_quadrature_gb = 0.0;
  EXPECT_THROW(immerse_solid(block, o), nurbs::InputError);
}

}  // namespace
}  // namespace isospring::geometry
