// Numbers a double cannot hold (1e999) in any input file are input errors naming the file, the
// line and column and the field; they used to escape as nlohmann's out_of_range (exit 4).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>

#include "isospring/io/case_file.hpp"
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

}  // namespace
}  // namespace isospring::io
