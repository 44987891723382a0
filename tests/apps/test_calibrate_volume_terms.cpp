// End-to-end: `isospring calibrate` with calibration.volume_terms on a small cantilever
// box. The written model.json carries the volume terms, its held-out error recomputed here from
// the file (spring statics with the volume terms, against a fresh IGA reference) is the one the
// report claims, and the engine exports refuse the model with a message naming what they lack.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
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
using isospring::testing::read_json;
using isospring::testing::run_isospring;
using isospring::testing::TemporaryFolder;
using nlohmann::json;

namespace {}  // namespace

TEST(CalibrateVolumeTerms, ModelCarriesThemAndItsHeldOutErrorIsTheWrittenModels) {
  TemporaryFolder out;
  json c = read_json(example("cantilever_box.json"));
  c["discretization"]["elements"] = {3, 1, 1};
  c["calibration"] = {{"grouping", {{"gamma", 0.01}}},
                      {"volume_terms", true},
                      {"holdout_load_cases", {"tip_side"}}};
  std::ofstream(out / "case.json") << c.dump();
  auto run = run_isospring("calibrate " + (out / "case.json") + " -o " + (out / "cal") + " -q");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const json report = read_json(out / "cal/report.json");
  const isospring::io::SpringModel model = isospring::io::read_model_json(out / "cal/model.json");
  ASSERT_GT(model.network.volumes.size(), 0u);
  EXPECT_EQ(report["volume_terms"].get<size_t>(), model.network.volumes.size());
  for (const auto& v : model.network.volumes) EXPECT_GT(v.modulus, 0.0);

  // Held-out tip_side, recomputed from the file: one patch, no gluing, particle = control point.
  using namespace isospring::analysis;
  const isospring::io::Case cs = isospring::io::read_case_file(out / "case.json");
  const DofMap dofs(cs.problem);
  const StaticResult reference = solve_static(cs.problem);
  double recomputed = NAN;
  for (size_t k = 0; k < cs.problem.load_cases.size(); ++k) {
    if (cs.problem.load_cases[k].id != "tip_side") continue;
    const Eigen::VectorXd f = assemble_load(cs.problem, dofs, cs.problem.load_cases[k]);
    const Eigen::VectorXd u = solve_spring_linear(model.network, f).displacement;
    const Eigen::VectorXd& u_ref = reference.load_cases[k].displacement;
    double o_max = 0, sum = 0;
    for (int a = 0; a < dofs.num_nodes(); ++a) {
      o_max = std::max(o_max, u_ref.segment(3 * a, 3).norm());
      sum += (u.segment(3 * a, 3) - u_ref.segment(3 * a, 3)).squaredNorm();
    }
    recomputed = 100 * std::sqrt(sum / dofs.num_nodes()) / o_max;
  }
  ASSERT_EQ(report["holdout"]["load_cases"].size(), 1u);
  EXPECT_NEAR(report["holdout"]["load_cases"][0]["percent_e_rms"].get<double>(), recomputed,
              1e-6 * recomputed);

  // SOFA has no such element: refused, with the reason. MuJoCo gets the springs as tendons
  // and the other terms beside the scene, for the runtime in its passive-force callback.
  run = run_isospring("export " + (out / "cal/model.json") + " -o " + (out / "model.scn") + " -q");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.output.find("volume terms"), std::string::npos) << run.output;
  run = run_isospring("export " + (out / "cal/model.json") + " -o " + (out / "model.xml") + " -q");
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(std::filesystem::exists(out / "model.isospring.json")) << run.output;
  // The matrix approach cannot be combined with volume terms: bad input, not a silent drop.
  c["calibration"]["matrix_approach"] = true;
  std::ofstream(out / "both.json") << c.dump();
  run = run_isospring("calibrate " + (out / "both.json") + " -o " + (out / "both") + " -q");
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_NE(run.output.find("matrix_approach"), std::string::npos) << run.output;
}
