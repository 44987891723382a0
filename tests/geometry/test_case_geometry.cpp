// The case-file "geometry" object: every type builds the primitive it names, and every mistake
// is an InputError naming the case file and the field.
#include <gtest/gtest.h>
#include <unistd.h>  // getpid: CTest runs tests in parallel processes

#include <BRepAlgoAPI_Cut.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "cad_test_io.hpp"
#include "isospring/geometry/measure.hpp"
#include "isospring/io/case_geometry.hpp"
#include "isospring/io/patch_file.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::io {
namespace {

using nlohmann::json;

std::vector<nurbs::Patch> build(const json& g) {
  return build_case_geometry(g, std::filesystem::temp_directory_path(), "case.json");
}

std::string error_of(const json& g) {
  try {
    build(g);
  } catch (const nurbs::InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(CaseGeometry, EveryTypeHasItsClosedFormMeasure) {
  const struct {
    json geometry;
    double measure;
  } cases[] = {
      {{{"type", "rectangle"}, {"size", {2.0, 0.5}}}, 1.0},
      {{{"type", "square"}, {"size", 2.0}}, 4.0},
      {{{"type", "box"}, {"size", {0.1, 0.02, 0.03}}}, 6e-5},
      {{{"type", "cube"}, {"size", 2.0}}, 8.0},
      {{{"type", "disk"}, {"radius", 1.0}}, M_PI},
      {{{"type", "disk"}, {"radius", 1.0}, {"patches", 5}, {"inner_fraction", 0.4}}, M_PI},
      {{{"type", "ellipse"}, {"radii", {1.0, 0.5}}}, M_PI / 2},
      {{{"type", "annulus"}, {"inner_radius", 1.0}, {"outer_radius", 2.0}, {"sweep_angle", 180}},
       1.5 * M_PI},
      {{{"type", "plate_with_hole"}, {"hole_radius", 1.0}, {"half_width", 4.0}, {"patches", 2}},
       16.0 - M_PI / 4},
      {{{"type", "tube"}, {"inner_radius", 1.0}, {"outer_radius", 2.0}, {"length", 2.0}},
       1.5 * M_PI},
      {{{"type", "torus"}, {"inner_radius", 0.5}, {"outer_radius", 1.25}},
       2 * M_PI * M_PI * 0.875 * 0.375 * 0.375},
      {{{"type", "torus"}, {"major_radius", 2.0}, {"minor_radius", 1.0}}, 4 * M_PI * M_PI},
      {{{"type", "hollow_sphere"}, {"inner_radius", 1.0}, {"outer_radius", 2.0}},
       M_PI / 2 * 7.0 / 3.0},
      {{{"type", "spheroid"}, {"half_length", 2.0}, {"radius", 0.5}}, 4.0 / 3.0 * M_PI * 0.5},
      {{{"type", "coupled_spheroid"}}, 2.0 / 3.0 * M_PI},
      {{{"type", "thin_plate"},
        {"region", {{"type", "disk"}, {"radius", 1.0}}},
        {"thickness", 0.1}},
       0.1 * M_PI},
  };
  for (const auto& c : cases)
    EXPECT_NEAR(geometry::measure(build(c.geometry)) / c.measure, 1.0, 1e-12) << c.geometry.dump();
}

TEST(CaseGeometry, PatchFileIsReadRelativeToTheCase) {
  const auto dir = std::filesystem::temp_directory_path() /
                   (std::string("isospring_case_geometry_test-") + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  write_patch_file(dir / "ring.json",
                   build({{"type", "annulus"}, {"inner_radius", 1.0}, {"outer_radius", 3.0}}));
  const auto patches =
      build_case_geometry({{"type", "patches"}, {"file", "ring.json"}}, dir, "case.json");
  EXPECT_NEAR(geometry::measure(patches) / (2 * M_PI), 1.0, 1e-12);
  EXPECT_NE(error_of({{"type", "patches"}, {"file", "missing.json"}}).find("geometry.file"),
            std::string::npos);
  std::filesystem::remove_all(dir);
}

TEST(CaseGeometry, MistakesNameTheCaseFileAndTheField) {
  EXPECT_EQ(error_of({{"type", "box"}, {"size", {1.0, 2.0}}}),
            "case.json: geometry.size must have 3 numbers for a box, got 2");
  EXPECT_EQ(
      error_of({{"type", "box"}, {"size", {1.0, 2.0, 3.0}}, {"sise", 1}})
          .rfind("case.json: geometry.sise: unknown field; did you mean 'size'? (allowed here:", 0),
      0u);
  EXPECT_NE(error_of({{"type", "boxx"}}).find("case.json: geometry.type 'boxx' is unknown"),
            std::string::npos);
  EXPECT_NE(error_of({{"size", 1}}).find("case.json: geometry.type is missing"), std::string::npos);
  EXPECT_NE(error_of({{"type", "box"}, {"size", {1.0, 0.0, 3.0}}}).find("size[1]"),
            std::string::npos);
  EXPECT_NE(error_of({{"type", "box"}, {"size", {1.0, "a", 3.0}}})
                .find("geometry.size[1] must be a number"),
            std::string::npos);
  EXPECT_NE(error_of({{"type", "disk"}}).find("geometry.radius is missing"), std::string::npos);
  EXPECT_NE(error_of({{"type", "disk"}, {"radius", 1}, {"patches", 3}}).find("geometry.patches"),
            std::string::npos);
  EXPECT_NE(error_of({{"type", "annulus"}, {"inner_radius", 2}, {"outer_radius", 1}})
                .find("case.json: geometry: annulus: inner_radius"),
            std::string::npos);
  EXPECT_NE(
      error_of(
          {{"type", "annulus"}, {"inner_radius", 1}, {"outer_radius", 2}, {"sweep_angle", 400}})
          .find("geometry.sweep_angle must be in (0, 360]"),
      std::string::npos);
  EXPECT_NE(error_of({{"type", "torus"}, {"major_radius", 2}, {"inner_radius", 1}})
                .find("geometry.major_radius"),
            std::string::npos);
  EXPECT_NE(
      error_of(
          {{"type", "thin_plate"}, {"region", {{"type", "cube"}, {"size", 1}}}, {"thickness", 0.1}})
          .find("geometry.region must be a 2D"),
      std::string::npos);
  EXPECT_NE(error_of({{"type", "thin_plate"},
                      {"region", {{"type", "square"}, {"size", 1}, {"x", 1}}},
                      {"thickness", 0.1}})
                .find("geometry.region.x: unknown field"),
            std::string::npos);
  EXPECT_NE(error_of(json::array()).find("case.json: geometry must be an object"),
            std::string::npos);
}

TEST(CaseGeometry, CadPartFromTheExamples) {
  const auto dir = std::filesystem::path(ISOSPRING_SOURCE_DIR) / "examples" / "cad";
  const auto block =
      build_case_geometry({{"type", "cad"}, {"file", "block.step"}}, dir, "case.json");
  EXPECT_NEAR(geometry::measure(block) / 4e-5, 1.0, 1e-13);
  const auto slab = build_case_geometry(
      {{"type", "cad"}, {"file", "block.step"}, {"faces", {0}}, {"thickness", 0.01}}, dir,
      "case.json");
  EXPECT_NEAR(geometry::measure(slab) / 4e-6, 1.0, 1e-13);
  EXPECT_THROW(build_case_geometry({{"type", "cad"}, {"file", "block.step"}, {"faces", {99}}}, dir,
                                   "case.json"),
               nurbs::InputError);
}

TEST(CaseGeometry, CadSolidsSelection) {
  const auto dir = std::filesystem::path(ISOSPRING_SOURCE_DIR) / "examples" / "cad";
  // The tube (radii 15 and 20 mm, 100 mm long) is one solid of revolution: 4 quarter volumes.
  const auto tube = build_case_geometry({{"type", "cad"}, {"file", "tube.step"}, {"solids", {0}}},
                                        dir, "case.json");
  ASSERT_EQ(tube.size(), 4u);
  EXPECT_NEAR(geometry::measure(tube) / (M_PI * (0.02 * 0.02 - 0.015 * 0.015) * 0.1), 1.0, 1e-12);
  auto message = [&](const json& g) {
    try {
      build_case_geometry(g, dir, "case.json");
    } catch (const nurbs::InputError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_NE(message({{"type", "cad"}, {"file", "tube.step"}, {"solids", {1}}})
                .find("solids[0] = 1 is not a solid of the part (it has 1"),
            std::string::npos);
  EXPECT_NE(message({{"type", "cad"}, {"file", "tube.step"}, {"solids", {0}}, {"faces", {0}}})
                .find("geometry.solids cannot be combined with faces"),
            std::string::npos);
  // The bracket is a block with a through-hole: 7 volume patches.
  const auto bracket = build_case_geometry(
      {{"type", "cad"}, {"file", "bracket.step"}, {"solids", {0}}}, dir, "case.json");
  EXPECT_EQ(bracket.size(), 7u);
  // A block with a blind hole is not a volume: the message says why and what to do.
  TopoDS_Shape blind = BRepPrimAPI_MakeBox(0.04, 0.04, 0.02).Shape();
  blind = BRepAlgoAPI_Cut(blind, BRepPrimAPI_MakeCylinder(
                                     gp_Ax2(gp_Pnt(0.02, 0.02, 0.01), gp_Dir(0, 0, 1)), 0.005, 0.01)
                                     .Shape())
              .Shape();
  const geometry::CadModel model = geometry::test::step_round_trip(blind, "blind.step");
  const std::string refusal = [&] {
    try {
      build_case_geometry({{"type", "cad"}, {"file", model.file.filename()}, {"solids", {0}}},
                          model.file.parent_path(), "case.json");
    } catch (const nurbs::InputError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  }();
  EXPECT_NE(refusal.find("solid 0 cannot be a volume patch"), std::string::npos) << refusal;
  EXPECT_NE(refusal.find("a hole ends inside the solid"), std::string::npos) << refusal;
}

TEST(CaseGeometry, HelpListsEveryType) {
  const std::string help = geometry_types_help();
  for (const char* type : {"rectangle", "box", "disk", "torus", "coupled_spheroid", "patches"})
    EXPECT_NE(help.find(type), std::string::npos) << type;
}

}  // namespace
}  // namespace isospring::io
