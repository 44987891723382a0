// Case files: `material.model` picks the constitutive law (linear by default, neo-Hookean or SVK
// for large deformation); a bad value or a finite-strain law in plane stress names the field.
#include <gtest/gtest.h>

#include "isospring/io/case_file.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::io {
namespace {
using nlohmann::json;

json cube(const json& model) {
  json doc = json::parse(R"({
    "name": "cube", "geometry": {"type": "box", "size": [0.1, 0.1, 0.1]},
    "discretization": {"degree": 2, "elements": 1},
    "material": {"E": 50000.0, "nu": 0.3},
    "boundary": [{"side": "w0", "fix": ["x", "y", "z"]}],
    "load_cases": [{"id": "pull", "tractions": [{"side": "w1", "value": [0, 0, 100.0]}]}]})");
  if (!model.is_null()) doc["material"]["model"] = model;
  return doc;
}

json square(const std::string& type, const json& model) {
  json doc = json::parse(R"({
    "name": "square", "geometry": {"type": "rectangle", "size": [0.1, 0.1]},
    "discretization": {"degree": 2, "elements": 1},
    "material": {"E": 50000.0, "nu": 0.3},
    "boundary": [{"side": "v0", "fix": ["x", "y"]}],
    "load_cases": [{"id": "pull", "tractions": [{"side": "v1", "value": [0, 100.0]}]}]})");
  doc["analysis"] = {{"type", type}};
  doc["material"]["model"] = model;
  return doc;
}

std::string error_of(const json& document) {
  try {
    build_case_from_json(document, "case.json");
  } catch (const nurbs::InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(CaseMaterialModel, LinearIsTheDefault) {
  EXPECT_FALSE(build_case_from_json(cube(nullptr), "case.json").nonlinear_material);
  EXPECT_FALSE(build_case_from_json(cube("linear"), "case.json").nonlinear_material);
}

TEST(CaseMaterialModel, NamesPickTheHyperelasticLaw) {
  EXPECT_EQ(build_case_from_json(cube("neo_hookean"), "case.json").nonlinear_material,
            analysis::HyperelasticMaterial::kNeoHookean);
  EXPECT_EQ(build_case_from_json(cube("svk"), "case.json").nonlinear_material,
            analysis::HyperelasticMaterial::kSaintVenantKirchhoff);
  EXPECT_EQ(
      build_case_from_json(square("plane_strain", "neo_hookean"), "case.json").nonlinear_material,
      analysis::HyperelasticMaterial::kNeoHookean);
}

TEST(CaseMaterialModel, UnknownNameListsTheChoices) {
  const std::string message = error_of(cube("neo_hooke"));
  EXPECT_EQ(message.rfind("case.json: material.model: unknown material model 'neo_hooke'", 0), 0u)
      << message;
  EXPECT_NE(message.find("did you mean 'neo_hookean'?"), std::string::npos) << message;
  EXPECT_NE(message.find("\"linear\" (default), \"neo_hookean\" or \"svk\""), std::string::npos)
      << message;
  EXPECT_EQ(error_of(cube(3)).rfind("case.json: material.model must be a string", 0), 0u)
      << error_of(cube(3));
}

TEST(CaseMaterialModel, FiniteStrainLawsRefusePlaneStress) {
  for (const char* model : {"neo_hookean", "svk"}) {
    const std::string message = error_of(square("plane_stress", model));
    EXPECT_EQ(message.rfind("case.json: material.model: '" + std::string(model) +
                                "' needs plane strain or a solid",
                            0),
              0u)
        << message;
  }
  EXPECT_FALSE(
      build_case_from_json(square("plane_stress", "linear"), "case.json").nonlinear_material);
}

}  // namespace
}  // namespace isospring::io
