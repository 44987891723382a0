// End-to-end: the ParaView output of `isospring analyze` (OUT/result.vtm), read back with VTK's
// XML readers. Independent checks: a constant-stress patch test (uniaxial tension of a
// rectangle / box: sigma_xx = T everywhere, von Mises = |T|, energy density T^2 / (2E), the
// linear exact displacement), the library's own post-processing at the written parameters, the
// CSV control displacements, and the Bezier cells' corners against the sampled grid.
#include <gtest/gtest.h>
#include <vtkCellData.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
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

void check_patch_test(bool three_d) {
  TemporaryFolder out;
  const double E = 1000, nu = 0.3, T = 10;
  std::ofstream(out / "case.json") << patch_test_case(three_d, E, nu, T).dump();
  const auto run =
      run_isospring("analyze " + (out / "case.json") + " -o " + (out / "res") + " --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  auto blocks = its::read_vtm(out.path() / "res" / "result.vtm");
  ASSERT_EQ(blocks.size(), 3u);  // geometry, geometry_bezier, control_net
  auto* grid = vtkUnstructuredGrid::SafeDownCast(blocks["geometry"]);
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
  check_patch_test(false);
}

TEST(AnalyzeVtk, SolidPatchTestHasTheConstantStressEverywhere) {
  check_patch_test(true);
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
