// Immersed grids that keep given coordinates as cell boundaries (ImmersionOptions::breaks,
// planar_face_coordinates) and cut cells holding only a sliver of the part (left out): the knots
// against their definition, the planar faces against the solid's construction, and an L-shaped
// block whose faces are all planar: with its faces' coordinates kept, no cell is cut and the
// quadrature's volume and centroid are OpenCascade's to round-off, graded or not.
#include <gtest/gtest.h>

#include <BRepAlgoAPI_Cut.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <cmath>
#include <cstdio>
#include <vector>

#include "../../geometry/src/cad_solid_shape.hpp"
#include "../../geometry/src/immersed_grading.hpp"
#include "isospring/geometry/immersed_cad.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::geometry {
namespace {

// Without grading planes each piece between breaks holds ceil(L / H) equal cells: on [0, 1] with
// H = 0.1 and a break at 0.25, 3 cells of 0.25 / 3 and 8 of 0.75 / 8; a break at an end, twice,
// or outside changes nothing.
TEST(GridBreaks, UniformPiecesBetweenBreaks) {
  const std::vector<double> t =
      detail::graded_ticks(0.0, 1.0, 10, {}, 0, {0.25, 1.0, 0.25, -0.5, 0.0, 2.0});
  ASSERT_EQ(t.size(), 12u);
  EXPECT_EQ(t[3], 0.25);
  for (size_t i = 1; i < t.size(); ++i)
    EXPECT_NEAR(t[i] - t[i - 1], i <= 3 ? 0.25 / 3 : 0.75 / 8, 1e-15);
  EXPECT_EQ(t.front(), 0.0);
  EXPECT_EQ(t.back(), 1.0);
  // Breaks on the uniform ticks give the uniform ticks.
  const std::vector<double> same = detail::graded_ticks(0.0, 1.0, 10, {}, 0, {0.3, 0.7});
  ASSERT_EQ(same.size(), 11u);
  for (size_t i = 0; i < same.size(); ++i)
    EXPECT_NEAR(same[i], 0.1 * static_cast<double>(i), 1e-15);
}

// Graded towards x = 0.2 with a break at 0.23: the break is a tick, the cells next to the plane
// are at most `smallest`, no cell is longer than H and neighbours grow by at most the ratio
// (within each piece, and across the break at most by the ratio of the two pieces' roundings).
TEST(GridBreaks, GradedPiecesKeepTheBreakAndTheProgression) {
  const double s = 0.004, r = 1.5, H = 0.1;
  const std::vector<double> t = detail::graded_ticks(0.0, 1.0, 10, {{0, 0.2, s, r}}, 0, {0.23});
  bool has_break = false;
  double at_plane = 1.0;
  for (size_t i = 1; i < t.size(); ++i) {
    const double length = t[i] - t[i - 1];
    ASSERT_GT(length, 0.0);
    EXPECT_LE(length, H * (1 + 1e-9));
    has_break = has_break || t[i] == 0.23;
    if (t[i - 1] <= 0.2 + 1e-12 && t[i] >= 0.2 - 1e-12) at_plane = std::min(at_plane, length);
    if (i >= 2) {
      EXPECT_LE(length / (t[i - 1] - t[i - 2]), 2.0 * r) << "at " << t[i];
    }
  }
  EXPECT_TRUE(has_break);
  EXPECT_LE(at_plane, s * (1 + 1e-3));
  EXPECT_GT(at_plane, s / r);
}

// An L section 0.037 x 0.029 (legs 0.011 and 0.013 thick), 0.017 deep, off every uniform grid
// plane, with a hole of radius 0.003 through the long leg along z.
CadSolid l_block(bool hole) {
  TopoDS_Shape l =
      BRepAlgoAPI_Cut(
          BRepPrimAPI_MakeBox(0.037, 0.029, 0.017).Shape(),
          BRepPrimAPI_MakeBox(gp_Pnt(0.011, 0.013, -0.01), gp_Pnt(0.05, 0.05, 0.05)).Shape())
          .Shape();
  if (hole)
    l = BRepAlgoAPI_Cut(l, BRepPrimAPI_MakeCylinder(
                               gp_Ax2(gp_Pnt(0.025, 0.0065, -0.01), gp_Dir(0, 0, 1)), 0.003, 0.05)
                               .Shape())
            .Shape();
  return detail::make_cad_solid(l, "L block");
}

TEST(GridBreaks, PlanarFaceCoordinatesOfAnLBlock) {
  const std::array<std::vector<double>, 3> at = planar_face_coordinates(l_block(true));
  const std::vector<double> expected[3] = {{0.0, 0.011, 0.037}, {0.0, 0.013, 0.029}, {0.0, 0.017}};
  for (int k = 0; k < 3; ++k) {
    ASSERT_EQ(at[static_cast<size_t>(k)].size(), expected[k].size()) << "axis " << k;
    for (size_t i = 0; i < expected[k].size(); ++i)
      EXPECT_NEAR(at[static_cast<size_t>(k)][i], expected[k][i], 1e-15) << "axis " << k;
  }
}

// With its planar faces' coordinates kept, the L block without a hole (uniform or graded towards
// its re-entrant edge) has its faces on grid planes: no cell is cut (the plain grid cuts 36
// uniform, 64 graded), and the cells' volume and centroid are OpenCascade's to round-off. The
// cells along those faces see lines ending about 1e-11 m short of them and topology breaks 1e-8 m
// in, within OpenCascade's confusion of the face: not a crossing. With the hole, the hole adds
// cut cells and the measures agree to the quadrature's tolerance.
TEST(GridBreaks, FacesOnGridPlanesKeepTheMeasures) {
  for (const bool graded : {false, true}) {
    const CadSolid solid = l_block(false);
    ImmersionOptions options;
    options.cell_size = 0.005;
    if (graded) options.grading = {{0, 0.011, 0.001, 1.5}, {1, 0.013, 0.001, 1.5}};
    ImmersionStats plain;
    immerse_solid(solid, options, &plain);
    EXPECT_GT(plain.cut_cells, 0);
    options.breaks = planar_face_coordinates(solid);
    ImmersionStats kept;
    const ImmersedDomain domain = immerse_solid(solid, options, &kept);
    std::printf("L block, graded %d: %d cut cells on the plain grid, %d with the faces kept\n",
                graded, plain.cut_cells, kept.cut_cells);
    EXPECT_EQ(kept.cut_cells, 0) << "graded " << graded;
    const SolidMeasures exact = measure_solid(solid), ours = measure_quadrature(domain);
    EXPECT_NEAR(ours.volume, exact.volume, 1e-12 * exact.volume);
    EXPECT_NEAR((ours.centroid - exact.centroid).norm(), 0.0, 1e-12 * std::cbrt(exact.volume));
    EXPECT_NEAR(ours.area, exact.area, 1e-9 * exact.area);

    const CadSolid holed = l_block(true);
    options.breaks = planar_face_coordinates(holed);
    ImmersionStats with_hole;
    const ImmersedDomain holed_domain = immerse_solid(holed, options, &with_hole);
    EXPECT_GT(with_hole.cut_cells, kept.cut_cells) << "graded " << graded;
    const SolidMeasures exact_holed = measure_solid(holed),
                        ours_holed = measure_quadrature(holed_domain);
    EXPECT_NEAR(ours_holed.volume, exact_holed.volume, 1e-6 * exact_holed.volume);
  }
  ImmersionOptions bad;
  bad.cell_size = 0.005;
  bad.breaks[1] = {0.01, std::nan("")};
  EXPECT_THROW(immerse_solid(l_block(false), bad), nurbs::InputError);
}

// A face a round-off away from a grid plane: a block 0.03 long in x, in a user box of 0.06 with
// 0.01 cells, its end face moved off the plane x = 0.03 by 5e-14 m (5e-12 of a cell) outwards.
// The cells beyond the plane hold a sliver of the part and are left out (the volume changes by
// the slivers' 5e-14 / 0.03 = 1.7e-12 of the part's); moved by 1e-7 of a cell (1e-9 m,
// a piece the quadrature resolves) they stay, cut.
TEST(GridBreaks, SliverCellsAreLeftOut) {
  for (const double off : {5e-14, 1e-9}) {
    const CadSolid solid =
        detail::make_cad_solid(BRepPrimAPI_MakeBox(0.03 + off, 0.02, 0.02).Shape(), "block");
    ImmersionOptions options;
    options.cells = {6, 2, 2};
    options.box_min = Eigen::Vector3d::Zero();
    options.box_max = Eigen::Vector3d(0.06, 0.02, 0.02);
    ImmersionStats stats;
    const ImmersedDomain domain = immerse_solid(solid, options, &stats);
    const SolidMeasures exact = measure_solid(solid), ours = measure_quadrature(domain);
    std::printf("block %.0e m off the grid plane: %d cut cells, %d slivers left out\n", off,
                stats.cut_cells, stats.sliver_cells);
    if (off < 1e-12) {
      EXPECT_EQ(stats.cut_cells, 0);
      EXPECT_EQ(stats.sliver_cells, 2 * 2);
      EXPECT_EQ(static_cast<int>(domain.cells.size()), 3 * 2 * 2);
      EXPECT_NEAR(ours.volume, exact.volume, 1e-11 * exact.volume);
    } else {
      EXPECT_EQ(stats.sliver_cells, 0);
      EXPECT_EQ(stats.cut_cells, 2 * 2);
      EXPECT_NEAR(ours.volume, exact.volume, 1e-10 * exact.volume);
    }
  }
}

}  // namespace
}  // namespace isospring::geometry
