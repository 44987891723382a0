// End-to-end: the ParaView output of `isospring analyze` (OUT/result.vtm), read back with VTK's
// XML readers (and ParaView's pvpython where installed), its size against the model's, and the
// timings of report.json. Independent checks: a constant-stress patch test (uniaxial tension of a
// rectangle / box: sigma_xx = T everywhere, von Mises = |T|, energy density T^2 / (2E), the
// linear exact displacement), the library's own post-processing at the written parameters, the
// CSV control displacements, and the Bezier cells' corners against the sampled grid.
#include <gtest/gtest.h>
#include <vtkCellData.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "isospring/analysis/post_processing.hpp"
#include "isospring/analysis/static_solver.hpp"
#include "isospring/io/case_file.hpp"
#include "isospring/nurbs/error.hpp"
#include "run_program.hpp"
#include "vtk_read.hpp"

using isospring::testing::example;
using isospring::testing::run_isospring;
using isospring::testing::TemporaryFolder;
using nlohmann::json;
namespace its = isospring::testing;

namespace {
// Uniaxial tension T along x of a rectangle (2D, plane stress) or box (3D) held by symmetry
// supports on x = 0, y = 0 (and z = 0): the exact solution is linear, so every degree reproduces
// it up to the solver's round-off.
json patch_test_case(bool three_d, double E, double nu, double T) {
  json c = {
      {"name", "patch_test"},
      {"material", {{"E", E}, {"nu", nu}}},
      {"boundary", {{{"side", "u0"}, {"symmetry", true}}, {{"side", "v0"}, {"symmetry", true}}}}};
  if (three_d) {
    c["geometry"] = {{"type", "box"}, {"size", {2.0, 1.0, 0.5}}};
    c["discretization"] = {{"degree", 2}, {"elements", {3, 2, 2}}};
    c["boundary"].push_back({{"side", "w0"}, {"symmetry", true}});
    c["load_cases"] = {{{"id", "pull"}, {"tractions", {{{"side", "u1"}, {"value", {T, 0, 0}}}}}}};
  } else {
    c["geometry"] = {{"type", "rectangle"}, {"size", {2.0, 1.0}}};
    c["discretization"] = {{"degree", 3}, {"elements", {3, 2}}};
    c["load_cases"] = {{{"id", "pull"}, {"tractions", {{{"side", "u1"}, {"value", {T, 0}}}}}}};
  }
  return c;
}

// The constant stress and the linear displacement at every point of a sampled block.
void check_sampled_block(vtkUnstructuredGrid* grid, bool three_d, double E, double nu, double T) {
  ASSERT_NE(grid, nullptr);
  vtkPointData* pd = grid->GetPointData();
  vtkDataArray* u = pd->GetArray("displacement_pull");
  vtkDataArray* s = pd->GetArray("stress_pull");
  vtkDataArray* vm = pd->GetArray("von_mises_pull");
  vtkDataArray* w = pd->GetArray("strain_energy_density_pull");
  ASSERT_TRUE(u && s && vm && w);
  ASSERT_EQ(s->GetNumberOfComponents(), 9);
  ASSERT_GT(grid->GetNumberOfPoints(), 100);
  // Round-off of the solve and the post-processing (condition number of K ~ 1e4 here): 1e-10
  // relative to the stress scale T and the displacement scale T L / E.
  const double tol = 1e-10;
  double worst_stress = 0, worst_u = 0;
  for (vtkIdType i = 0; i < grid->GetNumberOfPoints(); ++i) {
    const Eigen::Vector3d x = its::point(grid, i);
    Eigen::VectorXd exact_s = Eigen::VectorXd::Zero(9);
    exact_s(0) = T;
    worst_stress = std::max(worst_stress, (its::tuple(s, i) - exact_s).cwiseAbs().maxCoeff() / T);
    worst_stress = std::max(worst_stress, std::abs(its::tuple(vm, i)(0) - T) / T);
    worst_stress =
        std::max(worst_stress, std::abs(its::tuple(w, i)(0) - T * T / (2 * E)) / (T * T / (2 * E)));
    const Eigen::Vector3d exact_u(T * x.x() / E, -nu * T * x.y() / E,
                                  three_d ? -nu * T * x.z() / E : 0.0);
    worst_u = std::max(worst_u, (its::tuple(u, i) - exact_u).cwiseAbs().maxCoeff() / (2 * T / E));
  }
  EXPECT_LT(worst_stress, tol);
  EXPECT_LT(worst_u, tol);
}

// `flags` are added to the analyze command; `sampled` are the blocks with evaluated fields.
void check_patch_test(bool three_d, const std::string& flags, size_t block_count,
                      const std::vector<std::string>& sampled) {
  TemporaryFolder out;
  const double E = 1000, nu = 0.3, T = 10;
  std::ofstream(out / "case.json") << patch_test_case(three_d, E, nu, T).dump();
  const auto run = run_isospring("analyze " + (out / "case.json") + " -o " + (out / "res") +
                                 " --quiet " + flags);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  auto blocks = its::read_vtm(out.path() / "res" / "result.vtm");
  ASSERT_EQ(blocks.size(), block_count);
  for (const std::string& name : sampled) {
    SCOPED_TRACE(name);
    check_sampled_block(vtkUnstructuredGrid::SafeDownCast(blocks[name]), three_d, E, nu, T);
  }
  const double tol = 1e-10;
  // The control net carries the control-point displacements, which reproduce the linear field
  // exactly (affine invariance): u_i = exact(P_i).
  auto* net = vtkPolyData::SafeDownCast(blocks["control_net"]);
  ASSERT_NE(net, nullptr);
  vtkDataArray* un = net->GetPointData()->GetArray("displacement_pull");
  ASSERT_NE(un, nullptr);
  for (vtkIdType i = 0; i < net->GetNumberOfPoints(); ++i) {
    const Eigen::Vector3d x = its::point(net, i);
    const Eigen::Vector3d exact_u(T * x.x() / E, -nu * T * x.y() / E,
                                  three_d ? -nu * T * x.z() / E : 0.0);
    EXPECT_LT((its::tuple(un, i) - exact_u).cwiseAbs().maxCoeff(), tol * 2 * T / E) << i;
  }
  auto* bezier = vtkUnstructuredGrid::SafeDownCast(blocks["geometry_bezier"]);
  ASSERT_NE(bezier, nullptr);
  EXPECT_NE(bezier->GetPointData()->GetArray("displacement_pull"), nullptr);
  EXPECT_NE(bezier->GetPointData()->GetArray("RationalWeights"), nullptr);
}
}  // namespace

TEST(AnalyzeVtk, PlaneStressPatchTestHasTheConstantStressEverywhere) {
  // 2D: the sampled surface, the Bezier cells and the control net.
  check_patch_test(false, "", 3, {"geometry"});
}

TEST(AnalyzeVtk, SolidPatchTestHasTheConstantStressOnItsSurface) {
  // 3D default: the sampled outer surface, no sampled volume.
  check_patch_test(true, "", 3, {"boundary"});
}

TEST(AnalyzeVtk, SolidPatchTestHasTheConstantStressInTheSampledVolumeOnRequest) {
  check_patch_test(true, "--vtk-samples 2", 4, {"geometry", "boundary"});
}

TEST(AnalyzeVtk, KirschFieldsAreTheLibraryPostProcessingAtTheWrittenParameters) {
  TemporaryFolder out;
  const auto run =
      run_isospring("analyze " + example("kirsch_plate.json") + " -o " + out.path().string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("result.vtm"), std::string::npos);
  std::ifstream report_file(out / "report.json");
  const json report = json::parse(report_file);
  EXPECT_EQ(report["vtk_file"], "result.vtm");

  // The same solve here (deterministic), evaluated at the parameters the file records.
  const isospring::io::Case c = isospring::io::read_case_file(example("kirsch_plate.json"));
  const auto solved = isospring::analysis::solve_static(c.problem);
  const auto& lc = solved.load_cases.at(0);

  auto blocks = its::read_vtm(out.path() / "result.vtm");
  auto* grid = vtkUnstructuredGrid::SafeDownCast(blocks["geometry"]);
  ASSERT_NE(grid, nullptr);
  vtkPointData* pd = grid->GetPointData();
  vtkDataArray* param = pd->GetArray("parameter");
  vtkDataArray* u = pd->GetArray("displacement_tension_x");
  vtkDataArray* s = pd->GetArray("stress_tension_x");
  vtkDataArray* vm = pd->GetArray("von_mises_tension_x");
  vtkDataArray* w = pd->GetArray("strain_energy_density_tension_x");
  ASSERT_TRUE(param && u && s && vm && w);
  vtkDataArray* cell_patch = grid->GetCellData()->GetArray("patch");
  ASSERT_NE(cell_patch, nullptr);
  // Patch of every point from the cells that use it.
  std::vector<int> patch_of(static_cast<size_t>(grid->GetNumberOfPoints()), -1);
  for (vtkIdType cell = 0; cell < grid->GetNumberOfCells(); ++cell) {
    vtkIdType n = 0;
    const vtkIdType* ids = nullptr;
    grid->GetCellPoints(cell, n, ids);
    for (vtkIdType k = 0; k < n; ++k)
      patch_of[static_cast<size_t>(ids[k])] = static_cast<int>(cell_patch->GetTuple1(cell));
  }
  // Same numbers through the same code, written with 17 digits: only the last bit may differ.
  const double tol = 1e-13;
  double s_scale = 0, u_scale = lc.max_displacement;
  for (vtkIdType i = 0; i < grid->GetNumberOfPoints(); ++i)
    if (std::isfinite(its::tuple(vm, i)(0))) s_scale = std::max(s_scale, its::tuple(vm, i)(0));
  int degenerate = 0;
  ASSERT_GT(s_scale, 10.0);  // Kirsch: the peak von Mises stress at the hole is about 3 T = 30
  for (vtkIdType i = 0; i < grid->GetNumberOfPoints(); ++i) {
    const Eigen::VectorXd xi = its::tuple(param, i);
    const int patch = patch_of[static_cast<size_t>(i)];
    if (std::isnan(its::tuple(vm, i)(0))) {
      // Written as NaN only where the post-processing itself refuses: det J = 0.
      ++degenerate;
      EXPECT_THROW(isospring::analysis::evaluate_field(c.problem, lc.control_displacements, patch,
                                                       {xi(0), xi(1), xi(2)}),
                   isospring::nurbs::InputError);
      EXPECT_TRUE(its::tuple(s, i).array().isNaN().all());
      EXPECT_TRUE(std::isnan(its::tuple(w, i)(0)));
      continue;
    }
    const auto f = isospring::analysis::evaluate_field(c.problem, lc.control_displacements, patch,
                                                       {xi(0), xi(1), xi(2)});
    ASSERT_LT((its::point(grid, i) - f.point).norm(), 1e-13 * 4) << i;
    ASSERT_LT((its::tuple(u, i) - f.displacement).norm(), tol * u_scale) << i;
    Eigen::VectorXd stress(9);
    for (int r = 0; r < 3; ++r)
      for (int col = 0; col < 3; ++col) stress(3 * r + col) = f.stress(r, col);
    ASSERT_LT((its::tuple(s, i) - stress).norm(), tol * s_scale) << i;
    ASSERT_NEAR(its::tuple(vm, i)(0), f.von_mises, tol * s_scale) << i;
    ASSERT_NEAR(its::tuple(w, i)(0), 0.5 * f.stress.cwiseProduct(f.strain).sum(),
                tol * s_scale * s_scale / 1e5)
        << i;
  }
  // The 1-patch plate with a hole collapses the edge v = 1 onto the outer corner between its
  // two halves: exactly one sampled point (u = 0.5, v = 1) has det J = 0.
  EXPECT_EQ(degenerate, 1);
  // Bezier cells: their corner points interpolate, so they coincide with sampled points (the
  // element corners) and carry the same displacement.
  auto* bezier = vtkUnstructuredGrid::SafeDownCast(blocks["geometry_bezier"]);
  ASSERT_NE(bezier, nullptr);
  vtkDataArray* ub = bezier->GetPointData()->GetArray("displacement_tension_x");
  ASSERT_NE(ub, nullptr);
  int matched = 0;
  for (vtkIdType cell = 0; cell < bezier->GetNumberOfCells(); ++cell) {
    vtkIdType n = 0;
    const vtkIdType* ids = nullptr;
    bezier->GetCellPoints(cell, n, ids);
    for (vtkIdType k = 0; k < 4; ++k) {  // VTK lists a quadrilateral's 4 vertices first
      const Eigen::Vector3d x = its::point(bezier, ids[k]);
      for (vtkIdType i = 0; i < grid->GetNumberOfPoints(); ++i)
        if ((its::point(grid, i) - x).norm() < 1e-12) {
          EXPECT_LT((its::tuple(ub, ids[k]) - its::tuple(u, i)).norm(), 1e-12 * u_scale);
          ++matched;
          break;
        }
    }
  }
  EXPECT_EQ(matched, 4 * bezier->GetNumberOfCells());
  // The control net's displacements are the CSV table's.
  auto* net = vtkPolyData::SafeDownCast(blocks["control_net"]);
  ASSERT_NE(net, nullptr);
  vtkDataArray* un = net->GetPointData()->GetArray("displacement_tension_x");
  std::ifstream csv(out / "tension_x_control_displacements.csv");
  std::string line;
  std::getline(csv, line);
  vtkIdType rows = 0;
  while (std::getline(csv, line)) {
    std::stringstream fields(line);
    std::string cell;
    std::vector<double> v;
    while (std::getline(fields, cell, ',')) v.push_back(std::stod(cell));
    ASSERT_EQ(v.size(), 7u);
    EXPECT_EQ(its::tuple(un, rows), Eigen::Vector3d(v[4], v[5], v[6])) << rows;
    ++rows;
  }
  EXPECT_EQ(rows, net->GetNumberOfPoints());
}

namespace {
// A clamped box of n^3 elements of degree 2 under its own weight.
json cube_case(int n) {
  return {{"name", "cube"},
          {"geometry", {{"type", "box"}, {"size", {1.0, 1.0, 1.0}}}},
          {"discretization", {{"degree", 2}, {"elements", n}}},
          {"material", {{"E", 210e9}, {"nu", 0.3}, {"density", 7800.0}}},
          {"boundary", {{{"side", "u0"}, {"fix", {"x", "y", "z"}}}}},
          {"load_cases", {{{"id", "gravity"}, {"gravity", {0, 0, -9.81}}}}}};
}

json read_report(const TemporaryFolder& out, const std::string& folder) {
  std::ifstream in(out.path() / folder / "report.json");
  return json::parse(in);
}
}  // namespace

TEST(AnalyzeVtk, TimingsListEveryStageAndEveryFileWithItsSize) {
  TemporaryFolder out;
  std::ofstream(out / "case.json") << cube_case(3).dump();
  const auto run = run_isospring("analyze " + (out / "case.json") + " -o " + (out / "res") +
                                 " --quiet --timings");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const json report = read_report(out, "res");
  const json& t = report.at("timings");
  double stages = 0;
  for (const char* key : {"read_seconds", "refinement_seconds", "assembly_seconds", "setup_seconds",
                          "solve_seconds", "post_processing_seconds"}) {
    ASSERT_TRUE(t.contains(key)) << key;
    EXPECT_GE(t[key].get<double>(), 0.0) << key;
    stages += t[key].get<double>();
  }
  // Every file of the output folder but report.json, once, with its size on disk.
  std::set<std::string> listed;
  double output_seconds = 0;
  for (const json& o : t.at("outputs")) {
    const std::string file = o.at("file");
    EXPECT_TRUE(listed.insert(file).second) << file;
    EXPECT_EQ(o.at("bytes").get<std::uintmax_t>(),
              std::filesystem::file_size(out.path() / "res" / file))
        << file;
    output_seconds += o.at("seconds").get<double>();
  }
  std::set<std::string> on_disk;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(out.path() / "res"))
    if (entry.is_regular_file())
      on_disk.insert(std::filesystem::relative(entry.path(), out.path() / "res").generic_string());
  on_disk.erase("report.json");
  EXPECT_EQ(listed, on_disk);
  EXPECT_TRUE(on_disk.count("result/boundary_sampled.vtu"));
  EXPECT_FALSE(on_disk.count("result/geometry_sampled.vtu"));  // the volume only on request
  // The stages and the files before report.md happened within total_seconds, one after another.
  EXPECT_LE(stages, report.at("total_seconds").get<double>() + 1e-6);
  EXPECT_NEAR(t.at("output_seconds").get<double>(), output_seconds, 1e-9);
  // --timings printed a line per stage and per file.
  for (const std::string line : {"reading", "refinement", "assembly", "solves", "post-processing",
                                 "result/geometry_bezier.vtu", "report.md", "total"})
    EXPECT_NE(run.output.find(line), std::string::npos) << line << "\n" << run.output;
}

TEST(AnalyzeVtk, TheCaseFileAsksForTheSampledVolumeAndTheFlagWins) {
  TemporaryFolder out;
  json c = cube_case(2);
  c["output"] = {{"vtk_samples", 2}};
  std::ofstream(out / "case.json") << c.dump();
  ASSERT_EQ(
      run_isospring("analyze " + (out / "case.json") + " -o " + (out / "a") + " -q").exit_code, 0);
  EXPECT_TRUE(std::filesystem::exists(out.path() / "a" / "result" / "geometry_sampled.vtu"));
  ASSERT_EQ(
      run_isospring("analyze " + (out / "case.json") + " -o " + (out / "b") + " -q --vtk-samples 0")
          .exit_code,
      0);
  EXPECT_FALSE(std::filesystem::exists(out.path() / "b" / "result.vtm"));
  c["output"] = {{"vtk_sample", 2}};
  std::ofstream(out / "bad.json") << c.dump();
  const auto bad = run_isospring("analyze " + (out / "bad.json") + " -o " + (out / "c") + " -q");
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.output.find("output.vtk_sample"), std::string::npos) << bad.output;
}

// The default output grows with the model, not with samples^3 per element: from 4^3 to 8^3
// elements the DOFs grow 4.6 x (216 -> 1000 control points) and the files by no more than 1.5 x
// that; every file reads back through VTK's readers with points and cells.
TEST(AnalyzeVtk, DefaultOutputIsInProportionToTheModel) {
  TemporaryFolder out;
  std::map<int, double> bytes, dofs;
  for (int n : {4, 8}) {
    const std::string name = "cube" + std::to_string(n);
    std::ofstream(out / (name + ".json")) << cube_case(n).dump();
    ASSERT_EQ(run_isospring("analyze " + (out / (name + ".json")) + " -o " + (out / name) + " -q")
                  .exit_code,
              0);
    const json report = read_report(out, name);
    dofs[n] = report.at("dofs").get<double>();
    bytes[n] = report.at("timings").at("output_bytes").get<double>();
    const auto blocks = its::read_vtm(out.path() / name / "result.vtm");
    ASSERT_EQ(blocks.size(), 3u);
    for (const auto& [block, data] : blocks) {
      auto* set = vtkDataSet::SafeDownCast(data);
      ASSERT_NE(set, nullptr) << block;
      EXPECT_GT(set->GetNumberOfPoints(), 0) << block;
      EXPECT_GT(set->GetNumberOfCells(), 0) << block;
    }
  }
  EXPECT_LT(bytes[8] / bytes[4], 1.5 * dofs[8] / dofs[4]) << bytes[4] << " " << bytes[8];
}

// ParaView itself loads the output, where it is installed (pvpython on PATH).
TEST(AnalyzeVtk, ParaViewLoadsTheOutput) {
  if (isospring::testing::run_program("command -v pvpython").exit_code != 0)
    GTEST_SKIP() << "ParaView's pvpython is not installed: VTK's readers check the files above";
  TemporaryFolder out;
  std::ofstream(out / "case.json") << cube_case(2).dump();
  ASSERT_EQ(
      run_isospring("analyze " + (out / "case.json") + " -o " + (out / "res") + " -q").exit_code,
      0);
  std::ofstream(out / "load.py")
      << "from paraview.simple import *\n"
         "import sys\n"
         "r = OpenDataFile(sys.argv[1])\n"
         "r.UpdatePipeline()\n"
         "info = r.GetDataInformation()\n"
         "print('points', info.GetNumberOfPoints(), 'cells', info.GetNumberOfCells())\n"
         "sys.exit(0 if info.GetNumberOfPoints() > 0 and info.GetNumberOfCells() > 0 else 1)\n";
  const auto run = isospring::testing::run_program("pvpython " + (out / "load.py") + " " +
                                                   (out / "res/result.vtm"));
  EXPECT_EQ(run.exit_code, 0) << run.output;
}
