// STEP entities OpenCascade cannot read: outside the geometry (a presentation style, a validation
// property, a unit with an unusual parameter count) they are a warning when the shape transfers
// and is valid; inside it (a point, a direction, the length unit) the file is refused.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "isospring/geometry/cad.hpp"
#include "isospring/geometry/immersed_cad.hpp"
#include "isospring/nurbs/error.hpp"

namespace fs = std::filesystem;

namespace isospring::geometry {
namespace {

std::string block_step() {
  std::ifstream in(fs::path(ISOSPRING_SOURCE_DIR) / "examples/cad/block.step");
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string replaced(std::string text, const std::string& what, const std::string& by) {
  const size_t at = text.find(what);
  EXPECT_NE(at, std::string::npos) << what;
  if (at != std::string::npos) text.replace(at, what.size(), by);
  return text;
}

// The block with `entities` added at the end of its DATA section.
std::string with_entities(const std::string& entities) {
  std::string text = block_step();
  const size_t end = text.rfind("ENDSEC;");
  return text.insert(end, entities);
}

fs::path write(const std::string& name, const std::string& text) {
  const fs::path dir =
      fs::temp_directory_path() / ("isospring_test_unreadable-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / name) << text;
  return dir / name;
}

// The block's #15 is its MANIFOLD_SOLID_BREP, #5 its PRODUCT_DEFINITION, #345 its context.
const char* const kPointStyle =
    "#1001 = STYLED_ITEM('',(#1002),#15);\n"
    "#1002 = PRESENTATION_STYLE_ASSIGNMENT((#1003));\n"
    "#1003 = POINT_STYLE('',#1004);\n"
    "#1004 = COLOUR_RGB('',1.,0.,0.);\n";
const char* const kValueRange =
    "#1010 = PROPERTY_DEFINITION('geometric validation property','volume',#5);\n"
    "#1011 = PROPERTY_DEFINITION_REPRESENTATION(#1010,#1012);\n"
    "#1012 = REPRESENTATION('volume',(#1013),#345);\n"
    "#1013 = VALUE_RANGE('tolerance');\n";

void expect_warning(const fs::path& file, const std::string& entity) {
  const CadModel model = read_cad(file);
  ASSERT_EQ(model.warnings.size(), 1u);
  EXPECT_NE(model.warnings[0].find(entity), std::string::npos) << model.warnings[0];
  EXPECT_NE(model.warnings[0].find(file.string()), std::string::npos) << model.warnings[0];
  EXPECT_NE(describe(model).find("warning: "), std::string::npos);
  EXPECT_EQ(model.solids, 1);
  EXPECT_NEAR(model.volume, 0.1 * 0.02 * 0.02, 1e-15);
  EXPECT_EQ(model.volume_patches.size(), 1u);
  // The immersed path reads it too.
  EXPECT_NEAR(measure_solid(read_cad_solid(file)).volume, 0.1 * 0.02 * 0.02, 1e-15);
}

void expect_refused(const fs::path& file, const std::string& what) {
  try {
    read_cad(file);
    FAIL() << file << " accepted";
  } catch (const nurbs::InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("corrupted"), std::string::npos) << message;
    EXPECT_NE(message.find(what), std::string::npos) << message;
  }
}

TEST(UnreadableStepEntities, TheBlockItselfHasNoWarnings) {
  EXPECT_TRUE(read_cad(write("block.step", block_step())).warnings.empty());
}

TEST(UnreadableStepEntities, PointStyleOfAPresentationIsAWarning) {
  expect_warning(write("point_style.step", with_entities(kPointStyle)), "#1003 POINT_STYLE");
}

TEST(UnreadableStepEntities, ValueRangeOfAValidationPropertyIsAWarning) {
  expect_warning(write("value_range.step", with_entities(kValueRange)), "#1013 VALUE_RANGE");
}

TEST(UnreadableStepEntities, SolidAngleUnitWithAnExtraParameterIsAWarning) {
  expect_warning(write("unit.step", replaced(block_step(), "SI_UNIT($,.STERADIAN.)",
                                             "SI_UNIT($,.STERADIAN.,$)")),
                 "#348");
}

TEST(UnreadableStepEntities, SeveralHarmlessOnesMakeOneWarning) {
  const CadModel model =
      read_cad(write("both.step", with_entities(std::string(kPointStyle) + kValueRange)));
  ASSERT_EQ(model.warnings.size(), 1u);
  EXPECT_NE(model.warnings[0].find("2 entities"), std::string::npos) << model.warnings[0];
}

TEST(UnreadableStepEntities, GeometryOrLengthUnitStaysAnError) {
  expect_refused(
      write("point.step", replaced(block_step(), "CARTESIAN_POINT(", "CARTESIAN_POINTX(")),
      "#11 AXIS2_PLACEMENT_3D");
  expect_refused(write("direction.step", replaced(block_step(), "DIRECTION(", "DIRECTIOM(")),
                 "#11 AXIS2_PLACEMENT_3D");
  expect_refused(write("length_unit.step",
                       replaced(block_step(), "SI_UNIT($,.METRE.)", "SI_UNIT($,.METRE.,$)")),
                 "#346");
  // A style that is unreadable and also referred to by a geometric item (a corrupted file that
  // happens to use a style's name) is geometry.
  expect_refused(
      write("styled_point.step",
            replaced(with_entities("#1020 = POINT_STYLE('',#1004);\n"
                                   "#1004 = COLOUR_RGB('',1.,0.,0.);\n"),
                     "#15 = MANIFOLD_SOLID_BREP('',#16);", "#15 = MANIFOLD_SOLID_BREP('',#1020);")),
      "POINT_STYLE");
}

}  // namespace
}  // namespace isospring::geometry
