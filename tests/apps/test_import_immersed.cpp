// End-to-end: `isospring import` on a part the body-fitted path refuses (a bracket with fillets
// and a hole, examples/immersed/rounded_bracket.step, built with OpenCascade) writes an immersed
// case that `isospring analyze` runs as written; the case edited with face selectors runs too.
// Independent checks: the supports' reaction against the weight or the traction's resultant from
// OpenCascade's volume and face areas (BRepGProp, in import's report), not from the program's
// quadrature; parts with body-fitted volumes keep that path; refusals name the fix and write
// nothing.
#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkUnstructuredGrid.h>

#include <Eigen/Core>
#include <Eigen/LU>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "run_program.hpp"
#include "vtk_read.hpp"

using isospring::testing::example;
using isospring::testing::read_json;
using isospring::testing::run_isospring;
using isospring::testing::TemporaryFolder;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

Eigen::Vector3d vec3(const json& j) {
  return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
}

bool contains(const std::string& text, const std::string& word) {
  return text.find(word) != std::string::npos;
}

TEST(ImportImmersed, RefusedPartGoesFromImportToAnalyze) {
  TemporaryFolder out;
  fs::copy_file(example("immersed/rounded_bracket.step"), out / "bracket.step");
  auto run = run_isospring("import " + (out / "bracket.step") + " -o " + (out / "bracket.json"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(contains(run.output, "immersed case")) << run.output;
  EXPECT_TRUE(contains(run.output, "isospring analyze")) << run.output;
  const json report = read_json(out.path() / "bracket.json.report.json");
  EXPECT_EQ(report.at("path"), "immersed");
  EXPECT_TRUE(contains(report.at("path_reason"), "cannot become body-fitted volume patches"));
  // The body-fitted notes stay in the report: why each face could not be a patch.
  EXPECT_EQ(report.at("faces").size(), 12u);
  const double volume = report.at("immersed").at("cad_volume");  // OpenCascade's BRepGProp
  EXPECT_NEAR(volume, report.at("cad_volume").get<double>(), 1e-12 * volume);
  // The case's grid follows the file's axes; the principal axes it names are a rotation.
  EXPECT_EQ(report.at("immersed").at("frame"), "file");
  Eigen::Matrix3d axes;
  for (int k = 0; k < 3; ++k) axes.col(k) = vec3(report.at("immersed").at("principal_axes").at(k));
  EXPECT_LT((axes.transpose() * axes - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  EXPECT_NEAR(axes.determinant(), 1.0, 1e-12);

  // The case: the part relative to the case's folder, every face listed, with the STEP names.
  const json c = read_json(out.path() / "bracket.json");
  EXPECT_EQ(c.at("geometry").at("file"), "bracket.step");
  ASSERT_EQ(c.at("faces").size(), 12u);
  double clamp_area = 0, load_area = 0, area = 0;
  for (const json& f : c.at("faces")) {
    area += f.at("area").get<double>();
    if (f.value("name", "") == "clamp") clamp_area = f.at("area");
    if (f.value("name", "") == "load_end") load_area = f.at("area");
  }
  EXPECT_NEAR(clamp_area, 0.030 * 0.028, 1e-15);  // the upright's back, 30 x 28 mm
  EXPECT_NEAR(load_area, 0.018 * 0.008, 1e-15);   // the base's end between its fillets
  EXPECT_NEAR(area, report.at("cad_area").get<double>(), 1e-12 * area);

  // As written: the placeholder clamp and the part's weight. The reaction balances the weight
  // from OpenCascade's volume to the quadrature's 1e-6 (docs/immersed.md).
  run = run_isospring("analyze " + (out / "bracket.json") + " -o " + (out / "res") + " --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const json result = read_json(out.path() / "res" / "report.json");
  EXPECT_EQ(result.at("path"), "immersed");
  const double weight = volume * 7850.0 * 9.81;
  const Eigen::Vector3d reaction = vec3(result.at("load_cases")[0].at("reaction_sum"));
  EXPECT_NEAR(reaction.z(), weight, 1e-5 * weight) << reaction.transpose();
  EXPECT_NEAR(reaction.head<2>().norm(), 0, 1e-5 * weight);
  EXPECT_TRUE(fs::exists(out.path() / "res" / "result.vtp"));

  // Edited as a user would: clamp by STEP name, the end face pulled up by a traction chosen by a
  // plane, a coarser grid. The reaction is minus the traction times OpenCascade's face area.
  json edited = c;
  edited["geometry"]["cells"] = {8, 4, 4};
  edited["output"] = {{"cells", true}};  // the background cells too (cells.vtu)
  edited["boundary"] = {{{"face", {{"name", "clamp"}}}, {"fix", {"x", "y", "z"}}}};
  edited["load_cases"] = {
      {{"id", "lift"},
       {"tractions",
        {{{"face", {{"plane", {{"point", {0.06, 0, 0}}, {"normal", {1, 0, 0}}}}}},
          {"value", {0, 0, 1e5}}}}}}};
  std::ofstream(out / "edited.json") << edited.dump();
  run = run_isospring("analyze " + (out / "edited.json") + " -o " + (out / "lift") + " --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const json lift = read_json(out.path() / "lift" / "report.json").at("load_cases")[0];
  const double force = 1e5 * load_area;
  EXPECT_NEAR(vec3(lift.at("reaction_sum")).z(), -force, 1e-5 * force) << lift.dump();
  EXPECT_NEAR(vec3(lift.at("applied_load")).z(), force, 1e-9 * force);
  EXPECT_GT(lift.at("max_displacement").get<double>(), 0);

  // The background cells, read back by VTK: the cut ones as many as the report says, every
  // share of a cell in (0, 1], and share x cell volume summed over the cells is the quadrature's
  // volume (to rounding) and OpenCascade's (to the quadrature's 1e-6).
  const json lift_report = read_json(out.path() / "lift" / "report.json");
  EXPECT_EQ(lift_report.at("cells_file"), "cells.vtu");
  auto cells = isospring::testing::read_vtu(out.path() / "lift" / "cells.vtu");
  ASSERT_NE(cells, nullptr);
  vtkDataArray* kind = cells->GetCellData()->GetArray("kind");
  vtkDataArray* fraction = cells->GetCellData()->GetArray("fraction");
  ASSERT_TRUE(kind && fraction);
  int cut = 0;
  double sum = 0;
  for (vtkIdType c = 0; c < cells->GetNumberOfCells(); ++c) {
    double bounds[6];
    cells->GetCell(c)->GetBounds(bounds);
    const double share = fraction->GetTuple1(c);
    EXPECT_GT(share, 0);
    EXPECT_LE(share, 1 + 1e-12);
    if (kind->GetTuple1(c) == 1)
      ++cut;
    else
      EXPECT_NEAR(share, 1, 1e-12);
    sum += share * (bounds[1] - bounds[0]) * (bounds[3] - bounds[2]) * (bounds[5] - bounds[4]);
  }
  EXPECT_EQ(cut, lift_report.at("immersion").at("cut_cells").get<int>());
  const double quadrature = lift_report.at("measures").at("quadrature").at("volume");
  EXPECT_NEAR(sum, quadrature, 1e-12 * quadrature);
  EXPECT_NEAR(sum, volume, 1e-6 * volume);
}

TEST(ImportImmersed, BodyFittedStaysTheDefaultAndImmersedIsOnRequest) {
  TemporaryFolder out;
  auto run =
      run_isospring("import " + example("cad/block.step") + " -o " + (out / "b.json") + " -q");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  json report = read_json(out.path() / "b.json.report.json");
  EXPECT_EQ(report.at("path"), "body-fitted");
  EXPECT_TRUE(contains(report.at("path_reason"), "body-fitted volume patches"));
  EXPECT_EQ(report.at("patch_count"), 1);

  // --path immersed on the same block: the case runs, and a block's cells are whole, so the
  // quadrature's volume is OpenCascade's to rounding.
  run = run_isospring("import " + example("cad/block.step") + " --path immersed -o " +
                      (out / "i.json") + " -q");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  report = read_json(out.path() / "i.json.report.json");
  EXPECT_EQ(report.at("path"), "immersed");
  EXPECT_TRUE(contains(report.at("path_reason"), "--path immersed"));
  const json c = read_json(out.path() / "i.json");
  EXPECT_EQ(c.at("faces").size(), 6u);
  run = run_isospring("analyze " + (out / "i.json") + " -o " + (out / "res") + " --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const json m = read_json(out.path() / "res" / "report.json").at("measures");
  EXPECT_LT(m.at("volume_relative_error").get<double>(), 1e-12);
}

TEST(ImportImmersed, RefusalsNameTheFixAndWriteNothing) {
  TemporaryFolder out;
  // Two solids, one immersed case: choose one.
  auto run = run_isospring("import " + example("immersed/cube_cylinder.step") +
                           " --path immersed -o " + (out / "cc.json"));
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_TRUE(contains(run.output, "--solids N")) << run.output;
  EXPECT_FALSE(fs::exists(out.path() / "cc.json"));
  run = run_isospring("import " + example("immersed/cube_cylinder.step") +
                      " --path immersed --solids 1 -o " + (out / "cc.json") + " -q");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(read_json(out.path() / "cc.json").at("geometry").at("solid"), 1);
  EXPECT_EQ(read_json(out.path() / "cc.json").at("faces").size(), 6u);  // the cube's

  run = run_isospring("import " + example("cad/block.step") + " --path immersed --faces 0 -o " +
                      (out / "f.json"));
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_TRUE(contains(run.output, "drop --faces")) << run.output;
  EXPECT_FALSE(fs::exists(out.path() / "f.json"));

  // The block with one face left out of its shell: an open shell, refused with the fix.
  std::string step = isospring::testing::file_contents(example("cad/block.step"));
  const std::string shell = "CLOSED_SHELL('',(#17,";
  ASSERT_NE(step.find(shell), std::string::npos);
  step.replace(step.find(shell), shell.size(), "CLOSED_SHELL('',(");
  std::ofstream(out / "open.step") << step;
  run =
      run_isospring("import " + (out / "open.step") + " --path immersed -o " + (out / "open.json"));
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_TRUE(contains(run.output, "open shell")) << run.output;
  EXPECT_FALSE(fs::exists(out.path() / "open.json"));
}

}  // namespace
