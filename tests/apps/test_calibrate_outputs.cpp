// End-to-end: the viewer and figure outputs of `isospring calibrate` (result.vtm, the error
// histogram and the error-vs-position plot) on examples/calibrate_square.json. The VTK fields
// are checked against independent computations: the reference against a fresh IGA solve, the
// model displacement against a linear solve of the written model.json, the error against the
// CSV table and the report's %e_max.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/dof_map.hpp"
#include "isospring/analysis/spring_static.hpp"
#include "isospring/analysis/static_solver.hpp"
#include "isospring/io/case_file.hpp"
#include "isospring/io/model_file.hpp"
#include "isospring/io/plot.hpp"
#include "run_program.hpp"
#include "vtk_read.hpp"

using isospring::testing::example;
using isospring::testing::run_isospring;
using isospring::testing::TemporaryFolder;
using nlohmann::json;
namespace its = isospring::testing;

namespace {
bool is_png(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[8] = {};
  in.read(magic, 8);
  return in && std::string(magic, 8) == std::string("\x89PNG\r\n\x1a\n", 8);
}
}  // namespace

TEST(CalibrateOutputs, ResultVtmHoldsReferenceModelAndErrorOfEveryLoadCase) {
  TemporaryFolder out;
  const auto run = run_isospring("calibrate " + example("calibrate_square.json") + " -o " +
                                 out.path().string() + " --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  std::ifstream report_file(out / "report.json");
  const json report = json::parse(report_file);
  EXPECT_EQ(report["vtk_file"], "result.vtm");

  auto blocks = its::read_vtm(out.path() / "result.vtm");
  ASSERT_EQ(blocks.size(), 4u);  // geometry, geometry_bezier, control_net, springs
  auto* net = vtkPolyData::SafeDownCast(blocks["control_net"]);
  auto* springs = vtkPolyData::SafeDownCast(blocks["springs"]);
  auto* geometry = vtkUnstructuredGrid::SafeDownCast(blocks["geometry"]);
  ASSERT_TRUE(net && springs && geometry && blocks["geometry_bezier"]);
  ASSERT_EQ(net->GetNumberOfPoints(), 36);
  ASSERT_EQ(springs->GetNumberOfPoints(), 36);
  ASSERT_EQ(springs->GetNumberOfLines(), 110);

  // Independent reference and model responses. One patch, no merged points: particle = node =
  // control point, in the same order on the net and in the network.
  using namespace isospring::analysis;
  const isospring::io::Case c = isospring::io::read_case_file(example("calibrate_square.json"));
  const SpringNetwork model = isospring::io::read_model_json(out / "model.json").network;
  const DofMap dofs(c.problem);
  const StaticResult reference = solve_static(c.problem);
  std::map<std::string, json> metrics;
  for (const char* role : {"fit", "holdout"})
    for (const json& lc : report[role]["load_cases"]) metrics[lc["id"]] = lc;
  ASSERT_EQ(metrics.size(), 4u);
  for (size_t k = 0; k < c.problem.load_cases.size(); ++k) {
    const std::string id = c.problem.load_cases[k].id;
    const Eigen::VectorXd f = assemble_load(c.problem, dofs, c.problem.load_cases[k]);
    const Eigen::VectorXd u_model = solve_spring_linear(model, f).displacement;
    const Eigen::VectorXd& u_ref = reference.load_cases[k].displacement;
    const double scale = metrics[id]["o_max"].get<double>();
    vtkDataArray* ref = net->GetPointData()->GetArray(("reference_" + id).c_str());
    vtkDataArray* mod = net->GetPointData()->GetArray(("model_" + id).c_str());
    vtkDataArray* err = net->GetPointData()->GetArray(("error_" + id).c_str());
    vtkDataArray* s_mod = springs->GetPointData()->GetArray(("model_" + id).c_str());
    vtkDataArray* s_err = springs->GetPointData()->GetArray(("error_" + id).c_str());
    ASSERT_TRUE(ref && mod && err && s_mod && s_err) << id;
    for (const char* name : {"reference_", "model_", "error_"})
      EXPECT_NE(geometry->GetPointData()->GetArray((name + id).c_str()), nullptr);
    // The CSV table of the same case.
    std::ifstream csv(out / (id + "_errors.csv"));
    std::string line;
    std::getline(csv, line);
    double max_error = 0, max_ref = 0;
    for (vtkIdType a = 0; a < 36; ++a) {
      ASSERT_TRUE(std::getline(csv, line));
      std::stringstream fields(line);
      std::string cell;
      std::vector<double> v;
      while (std::getline(fields, cell, ',')) v.push_back(std::stod(cell));
      const Eigen::Vector3d csv_error(v[4], v[5], v[6]);
      const Eigen::Vector3d r(u_ref(2 * a), u_ref(2 * a + 1), 0);
      const Eigen::Vector3d m(u_model(2 * a), u_model(2 * a + 1), 0);
      // Same solve (reference) and same network (model) with a different code path: round-off
      // of sparse Cholesky solves with condition numbers ~1e4, 1e-10 of o_max.
      EXPECT_LT((its::tuple(ref, a) - r).norm(), 1e-10 * scale) << id << " " << a;
      EXPECT_LT((its::tuple(mod, a) - m).norm(), 1e-9 * scale) << id << " " << a;
      EXPECT_LT((its::tuple(s_mod, a) - m).norm(), 1e-9 * scale) << id << " " << a;
      EXPECT_EQ(its::tuple(err, a), Eigen::VectorXd(csv_error)) << id << " " << a;
      EXPECT_EQ(its::tuple(s_err, a), Eigen::VectorXd(csv_error)) << id << " " << a;
      EXPECT_LT((its::tuple(mod, a) - its::tuple(ref, a) - csv_error).norm(), 1e-12 * scale);
      max_error = std::max(max_error, csv_error.norm());
      max_ref = std::max(max_ref, its::tuple(ref, a).norm());
    }
    EXPECT_NEAR(100 * max_error / max_ref, metrics[id]["percent_e_max"].get<double>(), 1e-9) << id;
  }

  // Figures: PNGs when gnuplot is installed, linked from report.md.
  std::ifstream md_file(out / "report.md");
  std::stringstream md;
  md << md_file.rdbuf();
  EXPECT_NE(md.str().find("result.vtm"), std::string::npos);
  if (!isospring::io::gnuplot_available()) {
    EXPECT_TRUE(report["figures"].empty());
    GTEST_SKIP() << "gnuplot not installed: figures not written (install gnuplot-nox)";
  }
  ASSERT_EQ(report["figures"], json({"errors_histogram.png", "errors_vs_position.png"}));
  for (const std::string figure : {"errors_histogram.png", "errors_vs_position.png"}) {
    EXPECT_TRUE(is_png(out.path() / figure)) << figure;
    EXPECT_GT(std::filesystem::file_size(out.path() / figure), 5000u) << figure;
    EXPECT_NE(md.str().find("](" + figure + ")"), std::string::npos) << figure;
  }
}
