// Case files: a valid case is translated faithfully, and every kind of bad input is an InputError
// whose message starts with the file name and names the field.
#include <gtest/gtest.h>
#include <unistd.h>  // getpid: CTest runs tests in parallel processes

#include <filesystem>
#include <fstream>

#include "isospring/io/case_file.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::io {
namespace {
using nlohmann::json;
namespace fs = std::filesystem;

json cantilever() {
  return json::parse(R"({
    "schema_version": 1, "name": "cantilever", "units": "SI",
    "geometry": {"type": "box", "size": [0.1, 0.02, 0.02]},
    "discretization": {"degree": [2, 2, 2], "elements": [6, 2, 2]},
    "material": {"E": 50000.0, "nu": 0.45, "density": 1100.0},
    "boundary": [{"side": "u0", "fix": ["x", "y", "z"]}],
    "load_cases": [{"id": "L1", "tractions": [{"side": "u1", "value": [0, 0, -100.0]}]},
                   {"id": "L2", "gravity": [0, 0, -9.81],
                    "point_loads": [{"control_point": [-1, -1, -1], "force": [0, 1, 0]}]}]})");
}

json plate() {
  return json::parse(R"({
    "name": "plate",
    "geometry": {"type": "rectangle", "size": [2.0, 1.0]},
    "discretization": {"degree": 3, "elements": [4, 2]},
    "analysis": {"type": "plane_strain", "thickness": 0.5},
    "material": {"E": 1e6, "nu": 0.3},
    "boundary": [{"side": "u0", "fix": ["x"]}, {"side": "v0", "symmetry": true},
                 {"control_point": 0, "fix": ["y"], "value": [0, 0.001]}],
    "load_cases": [{"id": "pull", "pressures": [{"side": "u1", "value": -5.0}]}]})");
}

std::string error_of(const json& document) {
  try {
    build_case_from_json(document, "case.json");
  } catch (const nurbs::InputError& e) {
    return e.what();
  }
  return "no error";
}

/// The message must start with the file name and the field, and mention `hint`.
void expect_error(const json& document, const std::string& field, const std::string& hint = "") {
  const std::string message = error_of(document);
  EXPECT_EQ(message.rfind("case.json: " + field, 0), 0u) << message;
  EXPECT_NE(message.find(hint), std::string::npos) << message;
}

TEST(CaseFile, CantileverIsTranslatedFaithfully) {
  const Case c = build_case_from_json(cantilever(), "some/dir/case.json");
  EXPECT_EQ(c.name, "cantilever");
  EXPECT_EQ(c.dimension, 3);
  const analysis::Problem& p = c.problem;
  EXPECT_EQ(p.formulation, analysis::Formulation::kSolid);
  EXPECT_EQ(p.material.youngs_modulus, 50000.0);
  EXPECT_EQ(p.material.poisson_ratio, 0.45);
  EXPECT_EQ(p.material.density, 1100.0);
  ASSERT_EQ(p.patches.size(), 1u);
  const nurbs::Patch& patch = p.patches[0];
  const int elements[3] = {6, 2, 2};
  for (int d = 0; d < 3; ++d) {
    EXPECT_EQ(patch.degree(d), 2);
    EXPECT_EQ(patch.knots(d).num_elements(), elements[d]);
    EXPECT_EQ(patch.num_points(d), elements[d] + 2);  // C1 quadratics: n + p basis functions
  }
  // Refinement is exact: corners of the box stay where they are.
  EXPECT_LT((patch.point({1, 1, 1}) - Eigen::Vector3d(0.1, 0.02, 0.02)).norm(), 1e-15);
  EXPECT_LT((patch.point({0.5, 0.5, 0.5}) - Eigen::Vector3d(0.05, 0.01, 0.01)).norm(), 1e-15);

  ASSERT_EQ(p.supports.size(), 1u);
  EXPECT_EQ(p.supports[0].side.dir, 0);
  EXPECT_EQ(p.supports[0].side.end, 0);
  EXPECT_TRUE(p.supports[0].fixed[0] && p.supports[0].fixed[1] && p.supports[0].fixed[2]);
  ASSERT_EQ(p.load_cases.size(), 2u);
  EXPECT_EQ(p.load_cases[0].id, "L1");
  ASSERT_EQ(p.load_cases[0].tractions.size(), 1u);
  EXPECT_EQ(p.load_cases[0].tractions[0].side.dir, 0);
  EXPECT_EQ(p.load_cases[0].tractions[0].side.end, 1);
  EXPECT_EQ(p.load_cases[0].tractions[0].value, Eigen::Vector3d(0, 0, -100));
  EXPECT_EQ(p.load_cases[1].gravity, Eigen::Vector3d(0, 0, -9.81));
  ASSERT_EQ(p.load_cases[1].point_loads.size(), 1u);
  // [-1, -1, -1] is the last control point of the net.
  EXPECT_EQ(p.load_cases[1].point_loads[0].control_point, patch.num_points() - 1);
}

TEST(CaseFile, PlaneCaseOptions) {
  const Case c = build_case_from_json(plate(), "case.json");
  EXPECT_EQ(c.dimension, 2);
  EXPECT_EQ(c.problem.formulation, analysis::Formulation::kPlaneStrain);
  EXPECT_EQ(c.problem.material.thickness, 0.5);
  EXPECT_EQ(c.problem.patches[0].degree(0), 3);
  EXPECT_EQ(c.problem.patches[0].knots(0).num_elements(), 4);
  EXPECT_EQ(c.problem.patches[0].knots(1).num_elements(), 2);
  ASSERT_EQ(c.problem.supports.size(), 3u);
  EXPECT_TRUE(c.problem.supports[1].symmetry);
  EXPECT_EQ(*c.problem.supports[2].control_point, 0);
  EXPECT_EQ(c.problem.supports[2].value, Eigen::Vector3d(0, 0.001, 0));
  EXPECT_FALSE(c.problem.supports[2].fixed[0]);
  EXPECT_EQ(c.problem.load_cases[0].pressures[0].value, -5.0);

  // Without "analysis", 2D geometry is plane stress with thickness 1.
  json doc = plate();
  doc.erase("analysis");
  const Case d = build_case_from_json(doc, "case.json");
  EXPECT_EQ(d.problem.formulation, analysis::Formulation::kPlaneStress);
  EXPECT_EQ(d.problem.material.thickness, 1.0);
}

TEST(CaseFile, ProblemAtAnotherDiscretisation) {
  const Case c = build_case_from_json(cantilever(), "case.json");
  CaseDiscretization finer{{3, 3, 3}, {12, 4, 4}};
  const analysis::Problem p = problem_at(c, finer);
  EXPECT_EQ(p.patches[0].degree(1), 3);
  EXPECT_EQ(p.patches[0].knots(0).num_elements(), 12);
  EXPECT_EQ(p.patches[0].num_points(), 15 * 7 * 7);
  // The net position [-1, -1, -1] follows the refinement.
  EXPECT_EQ(p.load_cases[1].point_loads[0].control_point, 15 * 7 * 7 - 1);
  EXPECT_EQ(p.supports.size(), c.problem.supports.size());
}

TEST(CaseFile, DiscretisationOfAGeometryWithInteriorKnots) {
  // The 1-patch plate with a hole has two knot spans along u: element counts must be multiples.
  json doc = plate();
  doc["geometry"] = {{"type", "plate_with_hole"}, {"hole_radius", 1.0}, {"half_width", 4.0}};
  doc["boundary"] = json::parse(R"([{"side": "u0", "symmetry": true},
                                    {"side": "u1", "symmetry": true}])");
  doc["load_cases"] =
      json::parse(R"([{"id": "T", "tractions": [{"side": "v1", "value": [1, 0]}]}])");
  doc["discretization"] = {{"degree", 2}, {"elements", {4, 3}}};
  const Case c = build_case_from_json(doc, "case.json");
  EXPECT_EQ(c.problem.patches[0].knots(0).num_elements(), 4);
  EXPECT_EQ(c.problem.patches[0].knots(1).num_elements(), 3);
  doc["discretization"]["elements"] = {3, 3};
  expect_error(doc, "discretization along u (patch 0)", "not a multiple of the 2 knot spans");
  doc["discretization"] = {{"degree", 1}};
  expect_error(doc, "discretization along u (patch 0)", "below the exact geometry's degree 2");
}

TEST(CaseFile, ReadsFromDiskAndResolvesMeasurements) {
  const fs::path dir = fs::temp_directory_path() /
                       (std::string("isospring_case_file_test-") + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "markers.csv") << "id,x,y,z\n";
  json doc = cantilever();
  doc["measurements"] = {{"file", "markers.csv"}, {"noise", 1e-5}};
  doc["calibration"] = {{"objective", "displacement"}};
  std::ofstream(dir / "case.json") << doc.dump(2);
  const Case c = read_case_file(dir / "case.json");
  ASSERT_TRUE(c.measurements.has_value());
  EXPECT_EQ(c.measurements->file, dir / "markers.csv");
  EXPECT_EQ(c.measurements->raw["noise"], 1e-5);
  EXPECT_EQ(c.calibration["objective"], "displacement");

  doc["measurements"]["file"] = "missing.csv";
  std::ofstream(dir / "case.json") << doc.dump(2);
  try {
    read_case_file(dir / "case.json");
    FAIL() << "missing measurement file accepted";
  } catch (const nurbs::InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("case.json: measurements.file: 'missing.csv' does not "
                                          "exist",
                                          0),
              0u)
        << e.what();
  }
  std::ofstream(dir / "broken.json") << "{\"name\": \"x\",";
  EXPECT_THROW(read_case_file(dir / "broken.json"), nurbs::InputError);
  EXPECT_THROW(read_case_file(dir / "absent.json"), nurbs::InputError);
  fs::remove_all(dir);
}

TEST(CaseFile, UnknownFieldsGetSuggestions) {
  json doc = cantilever();
  doc["load_cases"][0]["traction"] = doc["load_cases"][0]["tractions"];
  doc["load_cases"][0].erase("tractions");
  expect_error(doc, "load_cases[0].traction: unknown field; did you mean 'tractions'?");
  doc = cantilever();
  doc["materials"] = doc["material"];
  expect_error(doc, "materials: unknown field; did you mean 'material'?");
  doc = cantilever();
  doc["material"]["Young"] = 1.0;
  expect_error(doc, "material.Young: unknown field", "allowed here: E nu density");
  doc = cantilever();
  doc["boundary"][0]["fixed"] = {"x"};
  expect_error(doc, "boundary[0].fixed: unknown field; did you mean 'fix'?");
}

TEST(CaseFile, MissingAndMistypedFields) {
  json doc = cantilever();
  doc.erase("name");
  expect_error(doc, "name is missing");
  doc = cantilever();
  doc.erase("load_cases");
  expect_error(doc, "load_cases is missing");
  doc = cantilever();
  doc.erase("boundary");
  expect_error(doc, "boundary is missing");
  doc = cantilever();
  doc["material"]["E"] = "50000";
  expect_error(doc, "material.E must be a number, got string");
  doc = cantilever();
  doc["load_cases"][0]["tractions"][0]["value"] = {0, 0};
  expect_error(doc, "load_cases[0].tractions[0].value must be an array of 3 numbers, got 2");
  doc = cantilever();
  doc["discretization"]["elements"] = {6, 2};
  expect_error(doc, "discretization.elements must be one integer or 3 integers");
  doc = cantilever();
  doc["discretization"]["degree"] = {2, 0, 2};
  expect_error(doc, "discretization.degree must be >= 1");
  doc = cantilever();
  doc["schema_version"] = 2;
  expect_error(doc, "schema_version: this isospring reads schema version 1");
  doc = cantilever();
  doc["units"] = "mm";
  expect_error(doc, "units: 'mm' is not supported; isospring works in SI units");
  doc = cantilever();
  doc["geometry"]["size"] = {0.1, 0.02};
  expect_error(doc, "geometry.size");
}

TEST(CaseFile, NonFiniteNumbersAndMaterialRanges) {
  json doc = cantilever();
  doc["material"]["E"] = std::numeric_limits<double>::quiet_NaN();  // nlohmann stores NaN
  expect_error(doc, "material.E is not finite");
  doc = cantilever();
  doc["load_cases"][0]["tractions"][0]["value"][2] = std::numeric_limits<double>::infinity();
  expect_error(doc, "load_cases[0].tractions[0].value[2] is not finite");
  for (double E : {0.0, -1.0}) {
    doc = cantilever();
    doc["material"]["E"] = E;
    expect_error(doc, "material.E must be > 0");
  }
  for (double nu : {0.5, -1.0, 0.7}) {
    doc = cantilever();
    doc["material"]["nu"] = nu;
    expect_error(doc, "material.nu must be in (-1, 0.5)");
  }
  doc = cantilever();
  doc["material"]["density"] = -1.0;
  expect_error(doc, "material.density must be >= 0");
}

TEST(CaseFile, SidesAndSupports) {
  json doc = cantilever();
  doc["boundary"][0]["side"] = "x0";
  expect_error(doc, "boundary[0].side: unknown side 'x0'");
  doc = cantilever();
  doc["boundary"][0]["side"] = "u2";
  expect_error(doc, "boundary[0].side: unknown side 'u2'; did you mean");
  doc = plate();
  doc["boundary"][0]["side"] = "w0";
  expect_error(doc,
               "boundary[0].side: side 'w0' does not exist for a patch of parametric "
               "dimension 2");
  doc = plate();
  doc["boundary"][0]["fix"] = {"z"};
  expect_error(doc, "boundary[0].fix[0]: 'z' is not a displacement component");
  doc = cantilever();
  doc["boundary"][0]["patch"] = 1;
  expect_error(doc, "boundary[0].patch = 1 does not exist");
  doc = cantilever();
  doc["boundary"][0].erase("fix");
  expect_error(doc, "boundary[0]: say what is fixed");
  doc = cantilever();
  doc["boundary"][0]["symmetry"] = true;
  expect_error(doc, "boundary[0]: \"symmetry\": true fixes the normal component");
  doc = cantilever();
  doc["boundary"][0] = {{"control_point", 10000}, {"fix", {"x"}}};
  expect_error(doc, "boundary[0].control_point = 10000 is out of range");
  doc = cantilever();
  doc["boundary"][0]["value"] = "analytic";
  expect_error(doc, "boundary[0].value: \"analytic\" needs the case's top-level \"analytic\"");
}

// "where": {"x": c} names every patch side lying on the plane x = c (CAD parts cut into many
// patches); it must be the same as naming the sides, and a plane with no side is an error.
TEST(CaseFile, SidesByPlane) {
  json doc = cantilever();
  doc["boundary"][0] = {{"where", {{"x", 0.0}}}, {"fix", {"x", "y", "z"}}};
  doc["load_cases"][0]["tractions"][0] = {{"where", {{"x", 0.1}}}, {"value", {0, 0, -100.0}}};
  const Case c = build_case_from_json(doc, "case.json");
  ASSERT_EQ(c.problem.supports.size(), 1u);
  EXPECT_EQ(c.problem.supports[0].side.patch, 0);
  EXPECT_EQ(c.problem.supports[0].side.dir, 0);
  EXPECT_EQ(c.problem.supports[0].side.end, 0);
  EXPECT_TRUE(c.problem.supports[0].fixed[2]);
  ASSERT_EQ(c.problem.load_cases[0].tractions.size(), 1u);
  EXPECT_EQ(c.problem.load_cases[0].tractions[0].side.dir, 0);
  EXPECT_EQ(c.problem.load_cases[0].tractions[0].side.end, 1);
  EXPECT_EQ(c.problem.load_cases[0].tractions[0].value.z(), -100.0);
  // The bottom z = 0 is side w0.
  doc["load_cases"][0]["tractions"][0]["where"] = {{"z", 0.0}};
  const Case bottom = build_case_from_json(doc, "case.json");
  EXPECT_EQ(bottom.problem.load_cases[0].tractions[0].side.dir, 2);
  EXPECT_EQ(bottom.problem.load_cases[0].tractions[0].side.end, 0);

  doc = cantilever();
  doc["boundary"][0] = {{"where", {{"x", 0.05}}}, {"fix", {"x"}}};
  expect_error(doc, "boundary[0].where.x: no patch side lies on the plane x = 0.05",
               "the model spans x from 0 to 0.1");
  doc["boundary"][0]["where"] = {{"x", 0.0}, {"y", 0.0}};
  expect_error(doc, "boundary[0].where: give one coordinate");
  doc["boundary"][0]["where"] = {{"q", 0.0}};
  expect_error(doc, "boundary[0].where.q: unknown field");
  doc["boundary"][0] = {{"where", {{"x", 0.0}}}, {"side", "u0"}, {"fix", {"x"}}};
  expect_error(doc, "boundary[0]: give either \"where\"");
  doc = cantilever();
  doc["load_cases"][0]["tractions"][0] = {{"where", {{"x", 0.0}}}, {"value", {0, 0, 1.0}}};
  expect_error(doc, "load_cases[0].tractions[0].where: side u0 of patch 0 is fully fixed");
  doc = plate();
  doc["boundary"][0] = {{"where", {{"z", 0.0}}}, {"fix", {"x"}}};
  expect_error(doc, "boundary[0].where.z: 2D geometry has no z");
}

TEST(CaseFile, LoadCases) {
  json doc = cantilever();
  doc["load_cases"][1]["id"] = "L1";
  expect_error(doc, "load_cases[1].id: load case id 'L1' is used twice");
  doc = cantilever();
  doc["load_cases"][0] = {{"id", "L1"}};
  expect_error(doc, "load_cases[0] (id 'L1') has no load");
  doc = cantilever();
  doc["load_cases"][0] = {{"id", "L1"}, {"body_force", {0, 0, 0}}};
  expect_error(doc, "load_cases[0] (id 'L1') has no load");
  doc = cantilever();
  doc["load_cases"] = json::array();
  expect_error(doc, "load_cases must not be empty");
  doc = cantilever();
  doc["load_cases"][0]["tractions"][0]["side"] = "u0";
  expect_error(doc, "load_cases[0].tractions[0].side: side u0 of patch 0 is fully fixed");
  // A side fixed only partly may carry a load.
  doc["boundary"][0]["fix"] = {"x"};
  doc["boundary"].push_back({{"side", "w0"}, {"fix", {"y", "z"}}});
  EXPECT_EQ(error_of(doc), "no error");
  doc = cantilever();
  doc["material"].erase("density");
  expect_error(doc, "load_cases[1].gravity: gravity needs material.density > 0");
  doc = cantilever();
  doc["load_cases"][0]["id"] = "a/b";
  expect_error(doc, "load_cases[0].id: must be a non-empty name without spaces or slashes");
  doc = plate();
  doc["load_cases"][0]["body_force"] = {1.0, 0.0, 2.0};
  expect_error(doc, "load_cases[0].body_force: the z component must be 0 for 2D geometry");
}

TEST(CaseFile, AnalysisSection) {
  json doc = cantilever();
  doc["analysis"] = {{"type", "plane_stress"}};
  expect_error(doc, "analysis.type: 'plane_stress' needs 2D geometry");
  doc = plate();
  doc["analysis"] = {{"type", "plane_stres"}};
  expect_error(doc,
               "analysis.type: unknown analysis type 'plane_stres'; did you mean "
               "'plane_stress'?");
  doc = plate();
  doc["analysis"] = {{"type", "solid"}};
  expect_error(doc, "analysis.type: \"solid\" needs 3D geometry");
  doc = cantilever();
  doc["analysis"] = {{"thickness", 0.1}};
  expect_error(doc, "analysis.thickness: only 2D analyses have a thickness");
  doc = plate();
  doc["analysis"]["thickness"] = 0.0;
  expect_error(doc, "analysis.thickness must be > 0");
}

TEST(CaseFile, VolumetricTreatment) {
  EXPECT_EQ(build_case_from_json(cantilever(), "case.json").problem.volumetric,
            analysis::Volumetric::kDisplacement);
  json doc = cantilever();
  doc["analysis"] = {{"volumetric", "bbar"}};
  EXPECT_EQ(build_case_from_json(doc, "case.json").problem.volumetric, analysis::Volumetric::kBbar);
  doc = plate();
  doc["analysis"]["volumetric"] = "bbar";
  EXPECT_EQ(build_case_from_json(doc, "case.json").problem.volumetric, analysis::Volumetric::kBbar);
  doc["analysis"]["volumetric"] = "b-bar";
  expect_error(doc, "analysis.volumetric: unknown volumetric treatment 'b-bar'", "\"bbar\"");
  doc["analysis"] = {{"type", "plane_stress"}, {"volumetric", "bbar"}};
  expect_error(doc, "analysis.volumetric: \"bbar\" needs plane_strain or solid");
}

}  // namespace
}  // namespace isospring::io
