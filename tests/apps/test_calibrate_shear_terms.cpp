// End-to-end: `isospring calibrate` with calibration.volume_terms and calibration.shear_terms
// on a small cantilever box. model.json carries both kinds (shear terms as "mu"), the
// held-out error recomputed here from the file (spring statics with the cell terms, against a
// fresh IGA reference) is the one the report claims, the exports refuse the model naming the
// shear terms, and generalisation.shear_terms lets cross-validation choose.
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

TEST(CalibrateShearTerms, ModelCarriesThemAndItsHeldOutErrorIsTheWrittenModels) {
  TemporaryFolder out;
  json c = read_json(example("cantilever_box.json"));
  c["discretization"]["elements"] = {3, 1, 1};
  c["calibration"] = {{"grouping", {{"gamma", 0.2}}},
                      {"volume_terms", true},
                      {"shear_terms", true},
                      {"max_iterations", 1000},
                      {"holdout_load_cases", {"tip_side"}}};
  std::ofstream(out / "case.json") << c.dump();
  auto run = run_isospring("calibrate " + (out / "case.json") + " -o " + (out / "cal") + " -q");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const json report = read_json(out / "cal/report.json");
  const json written = read_json(out / "cal/model.json");
  size_t with_mu = 0;
  for (const auto& v : written["volumes"]) with_mu += v.contains("mu") ? 1 : 0;
  const isospring::io::SpringModel model = isospring::io::read_model_json(out / "cal/model.json");
  size_t shear = 0;
  for (const auto& v : model.network.volumes) {
    EXPECT_GT(v.modulus, 0.0);
    shear += v.kind == isospring::analysis::CellEnergy::kShear ? 1 : 0;
  }
  ASSERT_GT(shear, 0u);
  EXPECT_EQ(with_mu, shear);
  EXPECT_EQ(report["shear_terms"].get<size_t>(), shear);
  EXPECT_EQ(report["volume_terms"].get<size_t>(), model.network.volumes.size() - shear);

  // Held-out tip_side, recomputed from the file: one patch, no gluing, particle = control point.
  using namespace isospring::analysis;
  const isospring::io::Case cs = isospring::io::read_case_file(out / "case.json");
  const DofMap dofs(cs.problem);
  const StaticResult reference = solve_static(cs.problem);
  double recomputed = NAN, without_shear = NAN;
  SpringNetwork no_shear = model.network;
  std::erase_if(no_shear.volumes, [](const auto& v) { return v.kind == CellEnergy::kShear; });
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
    without_shear = percent(no_shear);
  }
  ASSERT_EQ(report["holdout"]["load_cases"].size(), 1u);
  EXPECT_NEAR(report["holdout"]["load_cases"][0]["percent_e_rms"].get<double>(), recomputed,
              1e-6 * recomputed);
  // The shear terms carry load: the same file without them predicts a different displacement.
  EXPECT_GT(std::abs(without_shear - recomputed), 1e-3 * recomputed);

  // Every cell modulus is bounded (10 times the constrained modulus): no cell runs off to rigid.
  const double e = cs.problem.material.youngs_modulus, nu = cs.problem.material.poisson_ratio;
  for (const auto& v : model.network.volumes)
    EXPECT_LE(v.modulus, 10.0 * e * (1 - nu) / ((1 + nu) * (1 - 2 * nu)) * (1 + 1e-9));
  // `simulate` runs the model with both integrators (forces and tangent of the shear terms).
  for (const char* integrator : {"implicit", "verlet"}) {
    run = run_isospring("simulate " + (out / "cal/model.json") + " -o " + (out / integrator) +
                        " --dt 1e-4 --steps 300 --every 300 --gravity 0,0,-9.81 --integrator " +
                        integrator + " -q");
    EXPECT_EQ(run.exit_code, 0) << integrator << ": " << run.output;
  }

  // SOFA has no such element: refused, with the reason. MuJoCo gets the springs as tendons
  // and the other terms beside the scene, for the runtime in its passive-force callback.
  run = run_isospring("export " + (out / "cal/model.json") + " -o " + (out / "model.scn") + " -q");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.output.find("shear terms"), std::string::npos) << run.output;
  run = run_isospring("export " + (out / "cal/model.json") + " -o " + (out / "model.xml") + " -q");
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(std::filesystem::exists(out / "model.isospring.json")) << run.output;

  // Cross-validation between springs + volume terms with and without shear terms.
  c["calibration"] = {{"volume_terms", true},
                      {"holdout_load_cases", {"tip_side"}},
                      {"generalisation",
                       {{"gammas", {0.2}},
                        {"prior_weights", json::array()},
                        {"shear_terms", {false, true}},
                        {"load_suite", true}}}};
  std::ofstream(out / "cv.json") << c.dump();
  run = run_isospring("calibrate " + (out / "cv.json") + " -o " + (out / "cv") + " -q");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const json cv = read_json(out / "cv/report.json");
  ASSERT_EQ(cv["generalisation"]["candidates"].size(), 2u);
  EXPECT_NE(cv["generalisation"]["candidates"][0]["shear_terms"],
            cv["generalisation"]["candidates"][1]["shear_terms"]);
  // Bad input: a non-boolean model kind is named.
  c["calibration"]["generalisation"]["shear_terms"] = {1};
  std::ofstream(out / "bad.json") << c.dump();
  run = run_isospring("calibrate " + (out / "bad.json") + " -o " + (out / "bad") + " -q");
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_NE(run.output.find("shear_terms"), std::string::npos) << run.output;
}
