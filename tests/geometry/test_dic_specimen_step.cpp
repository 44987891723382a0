// The DIC specimen (examples/dic_plate/specimen.step) from a STEP description: its two faces
// become conforming patches of exactly the published drawing.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include <TopoDS_Face.hxx>

#include "cad_test_io.hpp"
#include "dic_specimen_shape.hpp"
#include "isospring/analysis/dof_map.hpp"
#include "isospring/geometry/cad.hpp"
#include "isospring/geometry/construction.hpp"
#include "isospring/geometry/measure.hpp"
#include "planar_split_checks.hpp"

namespace isospring::geometry {
namespace {

namespace fs = std::filesystem;

// Area of the drawing [m^2]: the straight part less the hole, plus the fillet region: between
// x = -20 and -5 mm the width is 20 + 2 (25 - sqrt(25^2 - (x + 5)^2)) mm, whose integral over
// the 15 mm run is 20 * 15 + 2 (25 * 15 - (15/2 sqrt(625 - 225) + 625/2 asin(15/25))).
double drawing_area() {
  const double straight = 85.0 * 20.0 - M_PI * 16.0;
  const double circle_part = 7.5 * std::sqrt(625.0 - 225.0) + 312.5 * std::asin(0.6);
  const double fillet = 20.0 * 15.0 + 2.0 * (25.0 * 15.0 - circle_part);
  return (straight + fillet) * 1e-6;
}

TEST(DicSpecimenStep, ShippedFileIsTheDrawing) {
  const fs::path shipped = fs::path(ISOSPRING_SOURCE_DIR) / "examples/dic_plate/specimen.step";
  const CadModel model = read_cad(shipped);
  ASSERT_EQ(model.faces, 2);
  EXPECT_NEAR(model.area / drawing_area(), 1.0, 1e-9);
  const CadModel fresh = test::step_round_trip(test::dic_specimen_shape(), "dic_specimen.step");
  EXPECT_NEAR(fresh.area / model.area, 1.0, 1e-12);
  // The straight part is cut around its hole (6 patches), the fillet region is a Coons patch;
  // together 7 patches, conforming across the faces' shared edge x = -5 mm after the shared
  // sides get common knots, so the analysis glues them and nothing is left unglued.
  const std::vector<nurbs::Patch> patches = cad_patches(model, 0.0, {0, 1});
  EXPECT_EQ(patches.size(), 7u);
  EXPECT_NEAR(measure(patches) / drawing_area(), 1.0, 1e-12);
  for (const auto& p : patches) EXPECT_GT(jacobian_range(p, 6).min, 0.0);
  analysis::Problem problem;
  problem.formulation = analysis::Formulation::kPlaneStress;
  problem.patches = patches;
  const analysis::DofMap dofs(problem);
  EXPECT_TRUE(dofs.unglued_interfaces().empty());
  // Perimeter of the drawing (bottom, top, right end, left end, fillet arcs, hole): the sides
  // no two patches share.
  const double perimeter =
      (85.0 + 85.0 + 20.0 + 30.0 + 2.0 * 25.0 * std::asin(0.6) + 2.0 * M_PI * 4.0) * 1e-3;
  EXPECT_NEAR(test::unshared_side_length(patches, 1e-12) / perimeter, 1.0, 1e-12);
}

}  // namespace
}  // namespace isospring::geometry
