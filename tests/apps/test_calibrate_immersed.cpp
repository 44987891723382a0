// End-to-end: `isospring calibrate` on an immersed case (examples/immersed/
// rounded_bracket_calibrate.json, a filleted bracket with a hole in a 10 x 5 x 5 grid, one load
// case held out): the report
// has the held-out errors, the reference on the part is `isospring analyze`'s solution of the same
// case (result.vtp against analyze's, point by point), the surface error of result.vtp's two
// fields is the report's, and model.json passes the exporters' checks (MuJoCo, SOFA, VTK).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "run_program.hpp"
#include "vtk_read.hpp"

using isospring::testing::example;
using isospring::testing::read_json;
using isospring::testing::run_isospring;
using isospring::testing::TemporaryFolder;
using nlohmann::json;
namespace its = isospring::testing;

namespace {

TEST(CalibrateImmersed, HeldOutErrorsReferenceAndExports) {
  TemporaryFolder out;
  const std::string case_file = example("immersed/rounded_bracket_calibrate.json");
  auto run = run_isospring("calibrate " + case_file + " -o " + (out / "cal") + " --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  for (const char* file : {"report.json", "report.md", "model.json", "springs.vtp", "result.vtp",
                           "weight_errors.csv", "tip_down_errors.csv"})
    EXPECT_TRUE(std::filesystem::exists(out.path() / "cal" / file)) << file;
  const json report = read_json(out.path() / "cal" / "report.json");
  EXPECT_EQ(report["path"], "immersed");
  ASSERT_TRUE(report["holdout"].is_object());
  ASSERT_EQ(report["holdout"]["load_cases"].size(), 1u);
  const json& held = report["holdout"]["load_cases"][0];
  EXPECT_EQ(held["id"], "tip_down");
  const double held_rms = held["percent_e_rms"].get<double>();
  EXPECT_GT(held_rms, 0.0);
  EXPECT_LT(held_rms, 100.0);
  EXPECT_EQ(report["fit"]["load_cases"].size(), 3u);

  // The reference is the immersed solution `analyze` reports: the same fields on the same
  // triangulation (both split the part's display mesh to the grid's cells).
  run = run_isospring("analyze " + case_file + " -o " + (out / "ana") + " --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  auto calibrated = its::read_vtp(out.path() / "cal" / "result.vtp");
  auto analysed = its::read_vtp(out.path() / "ana" / "result.vtp");
  ASSERT_TRUE(calibrated && analysed);
  ASSERT_EQ(calibrated->GetNumberOfPoints(), analysed->GetNumberOfPoints());
  vtkDataArray* ref = calibrated->GetPointData()->GetArray("reference_tip_down");
  vtkDataArray* springs = calibrated->GetPointData()->GetArray("springs_tip_down");
  vtkDataArray* solved = analysed->GetPointData()->GetArray("displacement_tip_down");
  ASSERT_TRUE(ref && springs && solved);
  double largest = 0.0, difference = 0.0, worst_error = 0.0;
  for (vtkIdType i = 0; i < calibrated->GetNumberOfPoints(); ++i) {
    largest = std::max(largest, its::tuple(solved, i).norm());
    difference = std::max(difference, (its::tuple(ref, i) - its::tuple(solved, i)).norm());
    worst_error = std::max(worst_error, (its::tuple(springs, i) - its::tuple(ref, i)).norm());
  }
  EXPECT_LT(difference, 1e-10 * largest);
  // The spring model's field differs from the reference on the surface as the report says: its
  // surface %e_max is taken over the boundary quadrature points, these are the display points,
  // so the two agree in size (within a factor 2), not exactly.
  const double surface_max = held["surface_percent_e_max"].get<double>();
  EXPECT_GT(100.0 * worst_error / largest, 0.5 * surface_max);
  EXPECT_LT(100.0 * worst_error / largest, 2.0 * surface_max);

  // The calibrated model goes through the exporters' own checks.
  for (const char* target : {"model.xml", "model.scn", "model.vtp"}) {
    run = run_isospring("export " + (out / "cal/model.json") + " -o " + (out / target) + " -q");
    EXPECT_EQ(run.exit_code, 0) << target << ": " << run.output;
    EXPECT_TRUE(std::filesystem::exists(out.path() / target)) << target;
  }
}

TEST(CalibrateImmersed, SettingsWithoutAnImmersedFormAreRefusedBeforeWriting) {
  TemporaryFolder out;
  json c = read_json(example("immersed/rounded_bracket_calibrate.json"));
  c["geometry"]["file"] = example("immersed/rounded_bracket.step");
  c["calibration"]["matrix_approach"] = true;
  const auto file = out.path() / "case.json";
  std::ofstream(file) << c.dump();
  const auto run = run_isospring("calibrate " + file.string() + " -o " + (out / "cal"));
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.output.find("calibration.matrix_approach has no immersed form"), std::string::npos)
      << run.output;
  EXPECT_FALSE(std::filesystem::exists(out.path() / "cal" / "model.json"));
}

}  // namespace
