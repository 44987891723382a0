// Case-file checks made before refining or solving: a load case whose every entry is zero, and a
// discretisation far beyond the machine, are input errors reported at once.
#include <gtest/gtest.h>

#include <chrono>

#include "isospring/io/case_file.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::io {
namespace {
using nlohmann::json;

json small_box() {
  return json::parse(R"({
    "name": "box", "geometry": {"type": "box", "size": [0.1, 0.02, 0.02]},
    "discretization": {"degree": [2, 2, 2], "elements": [2, 1, 1]},
    "material": {"E": 50000.0, "nu": 0.3, "density": 1100.0},
    "boundary": [{"side": "u0", "fix": ["x", "y", "z"]}],
    "load_cases": [{"id": "L1", "tractions": [{"side": "u1", "value": [0, 0, -100.0]}]}]})");
}

std::string input_error(const json& document, const CaseLimits& limits = {}) {
  try {
    build_case_from_json(document, "case.json", limits);
  } catch (const nurbs::InputError& e) {
    return e.what();
  }
  return "no InputError";
}

TEST(CaseLimits, ALoadCaseOfZerosIsAnInputError) {
  json zero_traction = small_box();
  zero_traction["load_cases"][0]["tractions"][0]["value"] = {0, 0, 0};
  json zero_everything = small_box();
  zero_everything["load_cases"][0] = json::parse(R"({"id": "L1", "body_force": [0, 0, 0],
      "gravity": [0, 0, 0], "tractions": [{"side": "u1", "value": [0, 0, 0]}],
      "point_loads": [{"control_point": [-1, -1, -1], "force": [0, 0, 0]}]})");
  for (const json& document : {zero_traction, zero_everything}) {
    const std::string message = input_error(document);
    EXPECT_NE(message.find("case.json: load_cases[0] (id 'L1') has no load"), std::string::npos)
        << message;
  }
  json tiny = small_box();  // a tiny load is a load (its norm underflows, its value does not)
  tiny["load_cases"][0]["tractions"][0]["value"] = {1e-200, 0, 0};
  EXPECT_NO_THROW(build_case_from_json(tiny, "case.json"));
}

TEST(CaseLimits, ControlNetsBeyondTheMemoryAreRefusedBeforeRefining) {
  json huge = small_box();
  huge["discretization"]["elements"] = {100000, 1000, 1000};
  const auto start = std::chrono::steady_clock::now();
  const std::string message = input_error(huge);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 1.0);
  EXPECT_NE(message.find("case.json: discretization: 100000 x 1000 x 1000 elements"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("are available"), std::string::npos) << message;
}

TEST(CaseLimits, ASolveBeyondTheLimitIsRefusedWithTheEstimate) {
  json box = small_box();
  box["discretization"]["elements"] = {40, 8, 8};
  CaseLimits limits;
  limits.solve_memory_bytes = 1e6;
  limits.solve_memory_source = "--max-memory 0.001 GB";
  const std::string message = input_error(box, limits);
  // 42 x 10 x 10 control points, 3 DOFs each; (2p+1)^3 = 125 basis functions overlap.
  EXPECT_NE(message.find("1.26e+04 DOFs"), std::string::npos) << message;
  EXPECT_NE(message.find("(--max-memory 0.001 GB)"), std::string::npos) << message;
  limits.solve_memory_bytes = 1e9;  // the same case within the limit is read
  EXPECT_NO_THROW(build_case_from_json(box, "case.json", limits));
}

}  // namespace
}  // namespace isospring::io
