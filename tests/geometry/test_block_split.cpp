// The block split of orthogonal solids with through-holes (block_split.hpp, cad_block.cpp):
// exact volumes against closed forms and OpenCascade, conformity (the faces no two patches share
// are exactly the solid's surface), positive Jacobians, and refusals that say why.
#include <gtest/gtest.h>

#include <BRepAlgoAPI_Cut.hxx>
#include <BRepAlgoAPI_Fuse.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakePolygon.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakePrism.hxx>
#include <cmath>
#include <stdexcept>

#include "cad_test_io.hpp"
#include "isospring/geometry/block_split.hpp"
#include "isospring/geometry/cad.hpp"
#include "isospring/geometry/construction.hpp"
#include "isospring/geometry/measure.hpp"
#include "planar_split_checks.hpp"

namespace isospring::geometry {
namespace {

using Eigen::Vector3d;

ThroughHole circular_hole(int axis, double from, double to, double x, double y, double radius) {
  return {axis, from, to, {circular_arc(Vector3d(x, y, 0), radius, 0.0, 2.0 * M_PI)}};
}

// The box [0, 4] x [0, 4] x [0, 2] (its inside test fills the holes, as the contract allows).
BlockRegion box_region() {
  BlockRegion region;
  region.planes = {std::vector<double>{0, 4}, {0, 4}, {0, 2}};
  region.inside = [](const Vector3d& x) {
    return x.x() > 0 && x.x() < 4 && x.y() > 0 && x.y() < 4 && x.z() > 0 && x.z() < 2;
  };
  return region;
}

TEST(BlockSplit, BoxWithHolesAlongTwoAxesIsExactAndConforming) {
  // A hole of radius 0.3 along z at (x, y) = (1, 1) and one along x at (y, z) = (3, 1): their
  // squares meet the faces and share the y room between them.
  BlockRegion region = box_region();
  region.holes = {circular_hole(2, 0, 2, 1, 1, 0.3), circular_hole(0, 0, 4, 3, 1, 0.3)};
  const std::vector<nurbs::Patch> patches = split_block_region(region, 1e-12);
  const double hole = M_PI * 0.09;
  // Closed forms, to the accuracy of measure()'s Gauss rule on rational patches.
  EXPECT_NEAR(measure(patches) / (32.0 - hole * 2 - hole * 4), 1.0, 1e-12);
  for (const auto& p : patches) EXPECT_GT(jacobian_range(p, 4).min, 0.0);
  // The faces no two patches share are the solid's surface: the box's six sides less the four
  // hole openings, plus the two hole walls. A face glued to nothing inside the solid (a
  // T-junction, different knots or weights) would add its area.
  const double surface = 2 * (16 + 8 + 8) - 4 * hole + 2 * M_PI * 0.3 * (2 + 4);
  EXPECT_NEAR(test::unshared_face_area(patches, 1e-12) / surface, 1.0, 1e-12);
}

TEST(BlockSplit, RefusalsSayWhy) {
  auto refusal = [](const BlockRegion& region) {
    try {
      split_block_region(region, 1e-12);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  BlockRegion in_line = box_region();
  in_line.holes = {circular_hole(2, 0, 2, 4, 1, 0.3)};
  EXPECT_NE(refusal(in_line).find("a face of the solid is in line with the centre of hole 1"),
            std::string::npos)
      << refusal(in_line);
  BlockRegion crowded = box_region();
  crowded.holes = {circular_hole(2, 0, 2, 1, 1, 0.3), circular_hole(2, 0, 2, 1.5, 2.5, 0.3)};
  EXPECT_NE(refusal(crowded).find("too close to a face or to another hole"), std::string::npos)
      << refusal(crowded);
  BlockRegion overlapping = box_region();
  overlapping.holes = {circular_hole(2, 0, 2, 1, 1, 0.3), circular_hole(2, 0, 2, 1, 1, 0.2)};
  EXPECT_NE(refusal(overlapping).find("hole 1 and hole 2 overlap"), std::string::npos)
      << refusal(overlapping);
  BlockRegion outside = box_region();
  outside.inside = [](const Vector3d& x) { return x.z() > 1.0; };  // no material below z = 1
  outside.holes = {circular_hole(0, 0, 4, 2, 0.5, 0.2)};
  EXPECT_NE(refusal(outside).find("hole 1 does not run through solid material"), std::string::npos)
      << refusal(outside);
}

// An L section (legs 50 x 10 and 10 x 60 mm, 100 mm deep) with one hole through each leg, along
// different axes, made in OpenCascade and read back from STEP: the CAx-IF L-bracket's layout.
TopoDS_Shape l_block_with_holes() {
  BRepBuilderAPI_MakePolygon outline;
  for (auto [x, y] :
       {std::pair{0.0, 0.0}, {0.05, 0.0}, {0.05, 0.01}, {0.01, 0.01}, {0.01, 0.06}, {0.0, 0.06}})
    outline.Add(gp_Pnt(x, y, 0));
  outline.Close();
  TopoDS_Shape l =
      BRepPrimAPI_MakePrism(BRepBuilderAPI_MakeFace(outline.Wire()).Face(), gp_Vec(0, 0, 0.1))
          .Shape();
  l = BRepAlgoAPI_Cut(
          l, BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, 0.04, 0.05), gp_Dir(1, 0, 0)), 0.005, 0.01)
                 .Shape())
          .Shape();
  l = BRepAlgoAPI_Cut(
          l, BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0.03, 0, 0.03), gp_Dir(0, 1, 0)), 0.004, 0.01)
                 .Shape())
          .Shape();
  return l;
}

TEST(CadBlock, LSectionWithHolesThroughBothLegs) {
  const CadModel model = test::step_round_trip(l_block_with_holes(), "l_block_with_holes.step");
  ASSERT_EQ(model.solid_notes.size(), 1u);
  EXPECT_EQ(model.solid_notes[0], "");
  EXPECT_EQ(model.solid_remarks[0], "");
  const double exact = (0.05 * 0.01 + 0.01 * 0.05) * 0.1 - M_PI * (25e-6 + 16e-6) * 0.01;
  EXPECT_NEAR(measure(model.volume_patches) / exact, 1.0, 1e-12);
  EXPECT_NEAR(measure(model.volume_patches) / model.volume, 1.0, 1e-9);
  for (const auto& p : model.volume_patches) EXPECT_GT(jacobian_range(p, 4).min, 0.0);
  // Conforming: the unshared faces are the part's surface (OpenCascade's area).
  EXPECT_NEAR(test::unshared_face_area(model.volume_patches, 1e-12) / model.area, 1.0, 1e-9);
  EXPECT_NE(describe(model).find("solid 0: " + std::to_string(model.volume_patches.size()) +
                                 " volume patch(es)"),
            std::string::npos);
}

// A stepped block (a 2 x 2 x 1 box with a 1 x 1 x 1 box on one corner) is a prism along no
// axis; without holes it is a block of 2 + 1 boxes, glued, its volume and surface exact.
TEST(CadBlock, SteppedBlockWithoutHoles) {
  const TopoDS_Shape stepped =
      BRepAlgoAPI_Fuse(BRepPrimAPI_MakeBox(0.02, 0.02, 0.01).Shape(),
                       BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0.01), 0.01, 0.01, 0.01).Shape())
          .Shape();
  const CadModel model = test::step_round_trip(stepped, "stepped_block.step");
  ASSERT_EQ(model.solid_notes.size(), 1u);
  EXPECT_EQ(model.solid_notes[0], "");
  EXPECT_EQ(model.volume_patches.size(), 5u);  // 4 below (the grid's 2 x 2 cells), 1 on top
  EXPECT_NEAR(measure(model.volume_patches) / 5e-6, 1.0, 1e-12);
  EXPECT_NEAR(test::unshared_face_area(model.volume_patches, 1e-12) / model.area, 1.0, 1e-12);
}

}  // namespace
}  // namespace isospring::geometry
