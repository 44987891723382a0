// End-to-end: `isospring analyze` on an immersed case (examples/immersed/cylinder_gravity.json:
// a third-party cylinder clamped on one end disk under its own weight across its axis).
// Independent checks: the supports' reaction against the weight from OpenCascade's volume
// (BRepGProp) x density x g; the domain's volume against OpenCascade's; strain energy and largest
// displacement against the body-fitted analysis of the same solid; the VTK file read back with
// VTK's XML reader; bad input refused with the field named and nothing written.
#include <gtest/gtest.h>
#include <vtkCellData.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "isospring/geometry/immersed_cad.hpp"
#include "run_program.hpp"
#include "vtk_read.hpp"

using isospring::testing::example;
using isospring::testing::read_json;
using isospring::testing::run_isospring;
using isospring::testing::TemporaryFolder;
using nlohmann::json;
namespace its = isospring::testing;

namespace {

TEST(AnalyzeImmersed, CylinderUnderGravityBalancesItsWeight) {
  TemporaryFolder out;
  const std::string case_file = example("immersed/cylinder_gravity.json");
  const auto run = run_isospring("analyze " + case_file + " -o " + (out / "res") + " --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const json report = read_json(out.path() / "res" / "report.json");
  EXPECT_EQ(report.at("path"), "immersed");
  EXPECT_FALSE(report.at("path_reason").get<std::string>().empty());
  ASSERT_EQ(report.at("load_cases").size(), 1u);
  const json& lc = report.at("load_cases")[0];
  EXPECT_GT(lc.at("dofs").get<int>(), 0);
  EXPECT_GT(lc.at("strain_energy").get<double>(), 0);

  // The weight from OpenCascade's own volume, not from the program's quadrature.
  const json c = read_json(case_file);
  const auto solid = isospring::geometry::read_cad_solid(
      std::filesystem::path(case_file).parent_path() / c["geometry"]["file"].get<std::string>(),
      c["geometry"]["solid"].get<int>());
  const double volume = isospring::geometry::measure_solid(solid).volume;
  const double density = c["material"]["density"], g = 9.81;
  const double weight = volume * density * g;
  // The quadrature integrates the part to 1e-6 (docs/immersed.md); the report says so.
  EXPECT_NEAR(report["measures"]["quadrature"]["volume"].get<double>(), volume, 1e-6 * volume);
  // Equilibrium: the clamp pulls against gravity (+x) with the weight. The reaction is the
  // consistent one (analysis::immersed_reaction), which balances the quadrature's load up to the
  // ghost penalty's share: it checks the load's quadrature (volume to 1e-6), density and gravity
  // and the solve, not the stress. Measured: 2.5e-7 off the weight, the quadrature's volume error.
  const Eigen::Vector3d reaction(lc["reaction_sum"][0], lc["reaction_sum"][1],
                                 lc["reaction_sum"][2]);
  EXPECT_NEAR(reaction.x(), weight, 1e-5 * weight) << "reaction " << reaction.transpose();
  EXPECT_NEAR(reaction.y(), 0, 1e-9 * weight);
  EXPECT_NEAR(reaction.z(), 0, 1e-9 * weight);
  // The applied load is the quadrature's weight: the same to the volume's 1e-6.
  EXPECT_NEAR(lc["applied_load"][0].get<double>(), -weight, 1e-6 * weight);

  // ParaView's file: the part's surface with the fields, read back by VTK's XML reader.
  auto poly = its::read_vtp(out.path() / "res" / "result.vtp");
  ASSERT_NE(poly, nullptr);
  ASSERT_GT(poly->GetNumberOfPoints(), 50);
  ASSERT_GT(poly->GetNumberOfCells(), 50);
  vtkDataArray* u = poly->GetPointData()->GetArray("displacement_gravity");
  vtkDataArray* vm = poly->GetPointData()->GetArray("von_mises_gravity");
  ASSERT_TRUE(u && vm && poly->GetCellData()->GetArray("face"));
  double max_u = 0, min_ux = 0;
  for (vtkIdType i = 0; i < poly->GetNumberOfPoints(); ++i) {
    const Eigen::VectorXd ui = its::tuple(u, i);
    max_u = std::max(max_u, ui.norm());
    min_ux = std::min(min_ux, ui(0));
    EXPECT_GE(its::tuple(vm, i)(0), 0.0);
  }
  EXPECT_NEAR(max_u, lc["max_displacement"].get<double>(), 1e-12 * max_u);
  EXPECT_LT(min_ux, -0.9 * max_u);  // the part sags along gravity (-x)

  // Against what the immersed path does not share: the body-fitted analysis of the same STEP
  // solid (`isospring import`'s volumes of the cylinder, degree 3, 4 elements per direction,
  // supports imposed strongly on the end disk at z = 0; the part is symmetric about z = 5 mm, so
  // either end disk is the same clamp). Between 2 and 4 body-fitted elements the energy moves by
  // 0.8 % and the largest displacement by 0.9 % (the clamp's edge is singular), and the immersed
  // 4^3 and 6^3 grids differ by 0.6 % and 0.4 %: 1.5 % and 1 % bound the two discretisation errors.
  json fitted = {{"name", "cylinder_body_fitted"},
                 {"geometry",
                  {{"type", "cad"},
                   {"file", example("immersed/") + c["geometry"]["file"].get<std::string>()},
                   {"solids", {c["geometry"]["solid"]}}}},
                 {"discretization", {{"degree", 3}, {"elements", 4}}},
                 {"material", c["material"]},
                 {"boundary", {{{"where", {{"z", 0}}}, {"fix", {"x", "y", "z"}}}}},
                 {"load_cases", c["load_cases"]}};
  std::ofstream(out / "fitted.json") << fitted.dump();
  const auto run_fitted =
      run_isospring("analyze " + (out / "fitted.json") + " -o " + (out / "fitted") + " --quiet");
  ASSERT_EQ(run_fitted.exit_code, 0) << run_fitted.output;
  const json fitted_lc = read_json(out.path() / "fitted" / "report.json")["load_cases"][0];
  const double energy = fitted_lc["strain_energy"], displacement = fitted_lc["max_displacement"];
  EXPECT_NEAR(lc["strain_energy"].get<double>(), energy, 0.015 * energy);
  EXPECT_NEAR(lc["max_displacement"].get<double>(), displacement, 0.01 * displacement);
}

TEST(AnalyzeImmersed, BadFaceAndUnknownFieldAreNamed) {
  TemporaryFolder out;
  json c = read_json(example("immersed/cylinder_gravity.json"));
  c["geometry"]["file"] = example("immersed/cube_cylinder.step");
  json bad_face = c;
  bad_face["boundary"][0]["face"] = 42;
  std::ofstream(out / "face.json") << bad_face.dump();
  auto run = run_isospring("analyze " + (out / "face.json") + " -o " + (out / "r1") + " --quiet");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.output.find("face.json: boundary[0].face"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("isospring info"), std::string::npos) << run.output;
  EXPECT_FALSE(std::filesystem::exists(out.path() / "r1" / "report.json"));

  json typo = c;
  typo["geometry"]["cell"] = 4;
  std::ofstream(out / "typo.json") << typo.dump();
  run = run_isospring("analyze " + (out / "typo.json") + " -o " + (out / "r2") + " --quiet");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.output.find("typo.json: geometry.cell"), std::string::npos) << run.output;
  EXPECT_FALSE(std::filesystem::exists(out.path() / "r2" / "report.json"));
}

}  // namespace
