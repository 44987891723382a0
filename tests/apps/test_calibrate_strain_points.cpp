// End-to-end: `isospring calibrate` with calibration.strain_points on a small
// cantilever box. model.json carries the strain points ("points" and "gradients"), the held-out
// error recomputed here from the file (spring statics against a fresh IGA reference) is the one
// the report claims, `simulate` runs the model with both integrators, and the exports refuse it
// naming the strain points.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/dof_map.hpp"
#include "isospring/analysis/spring_static.hpp"
#include "isospring/analysis/static_solver.hpp"
#include "isospring/io/case_file.hpp"
#include "isospring/io/model_file.hpp"
#include "run_program.hpp"

using isospring::testing::example;
using isospring::testing::run_isospring;
using isospring::testing::TemporaryFolder;
using nlohmann::json;

TEST(CalibrateStrainPoints, ModelCarriesThemAndItsHeldOutErrorIsTheWrittenModels) {
  TemporaryFolder out;
  std::ifstream in(example("cantilever_box.json"));
  json c = json::parse(in);
  c["discretization"]["elements"] = {3, 1, 1};
  c["calibration"] = {{"grouping", {{"gamma", 0.2}}},
                      {"strain_points", 1},
                      {"max_iterations", 1000},
                      {"holdout_load_cases", {"tip_side"}}};
  std::ofstream(out / "case.json") << c.dump();
  auto run = run_isospring("calibrate " + (out / "case.json") + " -o " + (out / "cal") + " -q");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  std::ifstream report_in(out / "cal/report.json");
  const json report = json::parse(report_in);
  const isospring::io::SpringModel model = isospring::io::read_model_json(out / "cal/model.json");
  size_t points = 0;
  for (const auto& v : model.network.volumes) {
    EXPECT_GT(v.modulus, 0.0);
    EXPECT_EQ(v.points.size(), 27u);  // a degree-2 knot span's control points
    points += v.kind == isospring::analysis::CellEnergy::kShear ? 1 : 0;
  }
  EXPECT_EQ(points, 3u);  // one point in each of the 3 knot spans
  EXPECT_EQ(model.network.volumes.size(), 2 * points);
  EXPECT_EQ(report["strain_points"].get<size_t>(), points);
  EXPECT_EQ(report["volume_terms"].get<size_t>(), 0u);

  using namespace isospring::analysis;
  const isospring::io::Case cs = isospring::io::read_case_file(out / "case.json");
  const DofMap dofs(cs.problem);
  const StaticResult reference = solve_static(cs.problem);
  double recomputed = NAN, springs_only = NAN;
  SpringNetwork plain = model.network;
  plain.volumes.clear();
  for (size_t k = 0; k < cs.problem.load_cases.size(); ++k) {
    if (cs.problem.load_cases[k].id != "tip_side") continue;
    const Eigen::VectorXd f = assemble_load(cs.problem, dofs, cs.problem.load_cases[k]);
    const Eigen::VectorXd& u_ref = reference.load_cases[k].displacement;
    auto percent = [&](const SpringNetwork& net) {
      const Eigen::VectorXd u = solve_spring_linear(net, f).displacement;
      double o_max = 0, sum = 0;
      for (int a = 0; a < dofs.num_nodes(); ++a) {
        o_max = std::max(o_max, u_ref.segment(3 * a, 3).norm());
        sum += (u.segment(3 * a, 3) - u_ref.segment(3 * a, 3)).squaredNorm();
      }
      return 100 * std::sqrt(sum / dofs.num_nodes()) / o_max;
    };
    recomputed = percent(model.network);
    springs_only = percent(plain);
  }
  ASSERT_EQ(report["holdout"]["load_cases"].size(), 1u);
  EXPECT_NEAR(report["holdout"]["load_cases"][0]["percent_e_rms"].get<double>(), recomputed,
              1e-6 * recomputed);
  // The strain points carry load: the same file without them predicts a different displacement.
  EXPECT_GT(std::abs(springs_only - recomputed), 1e-3 * recomputed);

  for (const char* integrator : {"implicit", "verlet"}) {
    run = run_isospring("simulate " + (out / "cal/model.json") + " -o " + (out / integrator) +
                        " --dt 1e-4 --steps 300 --every 300 --gravity 0,0,-9.81 --integrator " +
                        integrator + " -q");
    EXPECT_EQ(run.exit_code, 0) << integrator << ": " << run.output;
  }
  // MuJoCo runs the strain points through the engine runtime (the terms beside the scene);
  // SOFA has no element for them and refuses the model, naming them.
  run = run_isospring("export " + (out / "cal/model.json") + " -o " + (out / "model.xml") + " -q");
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(std::filesystem::exists(out / "model.isospring.json"));
  run = run_isospring("export " + (out / "cal/model.json") + " -o " + (out / "model.scn") + " -q");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.output.find("strain points"), std::string::npos) << run.output;
}
