// Numbers a double cannot hold (1e999) in any input file are input errors naming the file, the
// line and column and the field; they used to escape as nlohmann's out_of_range (exit 4).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>

#include "isospring/io/case_file.hpp"
#include "isospring/io/case_geometry.hpp"
#include "isospring/io/json_text.hpp"
#include "isospring/io/model_file.hpp"
#include "isospring/io/patch_file.hpp"
#include "isospring/nurbs/error.hpp"
#include "run_program.hpp"

namespace isospring::io {
namespace {
namespace fs = std::filesystem;

std::string input_error(const std::function<void()>& read) {
  try {
    read();
  } catch (const nurbs::InputError& e) {
    return e.what();
  }
  return "no InputError";
}

TEST(JsonNumbers, AnOverflowNamesTheLineColumnAndField) {
  const std::string text = "{\"load_cases\": [\n  {\"id\": \"a\"},\n  {\"value\": [0, 1e999]}]}";
  const std::string message = input_error([&] { parse_json_text(text, "case.json", "case file"); });
  EXPECT_NE(message.find("case.json: line 3, column 17: load_cases[1].value[1] = 1e999"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("does not fit in a double"), std::string::npos) << message;
}

TEST(JsonNumbers, ASyntaxErrorNamesTheFileAndLine) {
  const std::string message =
      input_error([] { parse_json_text("{\n\"a\": [1, 2,]}", "p.json", "patch file"); });
  EXPECT_NE(message.find("p.json: line 2"), std::string::npos) << message;
  EXPECT_NE(message.find("not valid JSON"), std::string::npos) << message;
}

TEST(JsonNumbers, EveryInputFileReportsTheOverflowingField) {
  isospring::testing::TemporaryFolder dir;
  const std::string case_text = isospring::testing::file_contents(
      std::string(ISOSPRING_SOURCE_DIR) + "/examples/cantilever_box.json");
  const size_t at = case_text.find("\"E\": 50000.0");
  ASSERT_NE(at, std::string::npos);
  std::string overflowing = case_text;
  overflowing.replace(at, 12, "\"E\": 1e999");
  std::ofstream(dir / "case.json") << overflowing;
  std::ofstream(dir / "patches.json") << R"({"patches": [{"degrees": [1], "knots": [[0, 0, 1, 1]],
                         "control_points": [[0, 0, 0], [-1e400, 0, 0]]}]})";
  std::ofstream(dir / "model.json") << R"({"format": "isospring-spring-model", "particles": [
      {"position": [0, 0, 0], "mass": 1e999}]})";
  EXPECT_NE(input_error([&] { read_case_file(dir / "case.json"); }).find("material.E = 1e999"),
            std::string::npos);
  EXPECT_NE(input_error([&] {
              read_patch_file(dir / "patches.json");
            }).find("patches[0].control_points[1][0] = -1e400"),
            std::string::npos);
  EXPECT_NE(
      input_error([&] { read_model_json(dir / "model.json"); }).find("particles[0].mass = 1e999"),
      std::string::npos);
}

TEST(JsonNumbers, IntegersOnlyWhenTheyFitAnInt) {
  EXPECT_EQ(json_int(nlohmann::json::parse("2")), 2);
  EXPECT_EQ(json_int(nlohmann::json::parse("-2147483648")), -2147483647 - 1);
  EXPECT_EQ(json_int(nlohmann::json::parse("2147483647")), 2147483647);
  EXPECT_FALSE(json_int(nlohmann::json::parse("2147483648")));
  EXPECT_FALSE(json_int(nlohmann::json::parse("-2147483649")));
  EXPECT_FALSE(json_int(nlohmann::json::parse("4294967298")));  // get<int>() gives 2
  EXPECT_FALSE(json_int(nlohmann::json::parse("18446744073709551615")));
  EXPECT_FALSE(json_int(nlohmann::json::parse("2.0")));
  EXPECT_FALSE(json_int(nlohmann::json::parse("\"2\"")));
}

TEST(JsonNumbers, IntegersBeyondAnIntAreErrorsNotWrapped) {
  // Each of these used to be read modulo 2^32: degree 2, particle 0, a 5-patch disk, face 0.
  isospring::testing::TemporaryFolder dir;
  std::ofstream(dir / "patches.json") << R"({"patches": [{"degrees": [4294967298],
      "knots": [[0, 0, 0, 1, 1, 1]], "control_points": [[0, 0, 0], [1, 1, 0], [2, 0, 0]]}]})";
  EXPECT_NE(input_error([&] {
              read_patch_file(dir / "patches.json");
            }).find("degrees[0] is out of range for an integer (|n| <= 1e9), got 4294967298"),
            std::string::npos);
  std::ofstream(dir / "model.json") << R"({"format": "isospring-spring-model", "version": 1,
      "dimension": 3, "particles": [{"x": [0, 0, 0], "mass": 1, "fixed": true},
                                    {"x": [1, 0, 0], "mass": 1}],
      "springs": [{"i": 4294967296, "j": 1, "k": 1, "L0": 1}]})";
  EXPECT_NE(input_error([&] {
              read_model_json(dir / "model.json");
            }).find("springs[0].i is out of range for an integer (|n| <= 1e9), got 4294967296"),
            std::string::npos);
  const nlohmann::json disk = {{"type", "disk"}, {"radius", 1.0}, {"patches", 4294967301LL}};
  EXPECT_NE(input_error([&] {
              build_case_geometry(disk, dir.path(), "case.json");
            }).find("geometry.patches must be one of 1 5 for a disk, got 4294967301"),
            std::string::npos)
      << input_error([&] { build_case_geometry(disk, dir.path(), "case.json"); });
  const nlohmann::json cad = {
      {"type", "cad"},
      {"file", std::string(ISOSPRING_SOURCE_DIR) + "/examples/cad/block.step"},
      {"faces", {4294967296LL}}};
  EXPECT_NE(input_error([&] {
              build_case_geometry(cad, dir.path(), "case.json");
            }).find("must hold integers, got 4294967296"),
            std::string::npos)
      << input_error([&] { build_case_geometry(cad, dir.path(), "case.json"); });
}

}  // namespace
}  // namespace isospring::io
