// "analysis": {"volumetric": ...} is read by one function for body-fitted and immersed case files:
// a bad value gets the same message from both, naming the file, the field, the allowed values and
// the fix.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "isospring/io/case_file.hpp"
#include "isospring/io/immersed_case.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::io {
namespace {

using nlohmann::json;

json body_fitted(const std::string& volumetric) {
  json doc = json::parse(R"({
    "schema_version": 1, "name": "beam", "units": "SI",
    "geometry": {"type": "box", "size": [0.1, 0.02, 0.02]},
    "discretization": {"degree": [2, 2, 2], "elements": [4, 1, 1]},
    "material": {"E": 50000.0, "nu": 0.45},
    "boundary": [{"side": "u0", "fix": ["x", "y", "z"]}],
    "load_cases": [{"id": "L1", "tractions": [{"side": "u1", "value": [0, 0, -100.0]}]}]
  })");
  doc["analysis"] = {{"volumetric", volumetric}};
  return doc;
}

// The analysis object is read before the CAD file, so the part need not exist for this error.
json immersed(const std::string& volumetric) {
  json doc = json::parse(R"({
    "schema_version": 1, "name": "part", "units": "SI",
    "geometry": {"type": "immersed", "file": "part.step", "cell_size": 0.01},
    "material": {"E": 50000.0, "nu": 0.45},
    "boundary": [], "load_cases": []
  })");
  doc["analysis"] = {{"volumetric", volumetric}};
  return doc;
}

template <class Build>
std::string error_of(Build build) {
  try {
    build();
  } catch (const nurbs::InputError& e) {
    return e.what();
  }
  return "no error";
}

std::string body_fitted_error(const std::string& volumetric) {
  return error_of([&] { build_case_from_json(body_fitted(volumetric), "beam.json"); });
}

std::string immersed_error(const std::string& volumetric) {
  return error_of([&] { build_immersed_case(immersed(volumetric), "part.json"); });
}

const std::string kAllowed =
    " Allowed: \"displacement\" (the default: the displacement field's strain) or \"bbar\" (mean "
    "dilatation, locking-free for nu near 0.5); set one of them or leave \"volumetric\" out";

TEST(CaseVolumetric, BothCaseKindsGiveTheSameMessage) {
  const std::string text =
      "analysis.volumetric: unknown volumetric treatment 'bar'; did you mean 'bbar'?" + kAllowed;
  EXPECT_EQ(body_fitted_error("bar"), "beam.json: " + text);
  EXPECT_EQ(immersed_error("bar"), "part.json: " + text);
  // A value no allowed one is close to gets no suggestion.
  const std::string far =
      "analysis.volumetric: unknown volumetric treatment 'incompressible'." + kAllowed;
  EXPECT_EQ(body_fitted_error("incompressible"), "beam.json: " + far);
  EXPECT_EQ(immersed_error("incompressible"), "part.json: " + far);
}

TEST(CaseVolumetric, AllowedValuesAreAccepted) {
  EXPECT_EQ(build_case_from_json(body_fitted("bbar"), "beam.json").problem.volumetric,
            analysis::Volumetric::kBbar);
  EXPECT_EQ(build_case_from_json(body_fitted("displacement"), "beam.json").problem.volumetric,
            analysis::Volumetric::kDisplacement);
  // Past the analysis object the immersed reader wants the CAD file: the value was accepted.
  EXPECT_EQ(immersed_error("bbar").find("volumetric"), std::string::npos) << immersed_error("bbar");
}

}  // namespace
}  // namespace isospring::io
