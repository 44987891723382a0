// End-to-end: `isospring calibrate` on examples/calibrate_square.json. The report's errors are
// re-computed independently: the written model.json is solved here with the spring statics and
// compared with a fresh IGA reference of the same case.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>

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

namespace {
// %e_rms of the model's linear response against the IGA reference for one load case.
double recomputed_e_rms(const isospring::io::Case& c, const isospring::analysis::SpringNetwork& net,
                        const std::string& id) {
  using namespace isospring::analysis;
  const DofMap dofs(c.problem);
  const int dim = dofs.dofs_per_node();
  const StaticResult reference = solve_static(c.problem);
  for (size_t k = 0; k < c.problem.load_cases.size(); ++k) {
    if (c.problem.load_cases[k].id != id) continue;
    // One patch, no gluing: particle = node = control point.
    const Eigen::VectorXd f = assemble_load(c.problem, dofs, c.problem.load_cases[k]);
    const Eigen::VectorXd u = solve_spring_linear(net, f).displacement;
    const Eigen::VectorXd& u_ref = reference.load_cases[k].displacement;
    double o_max = 0, sum = 0;
    for (int a = 0; a < dofs.num_nodes(); ++a) {
      o_max = std::max(o_max, u_ref.segment(a * dim, dim).norm());
      sum += (u.segment(a * dim, dim) - u_ref.segment(a * dim, dim)).squaredNorm();
    }
    return 100 * std::sqrt(sum / dofs.num_nodes()) / o_max;
  }
  ADD_FAILURE() << "no load case " << id;
  return NAN;
}
}  // namespace

TEST(Calibrate, SquareReportMatchesAnIndependentSolveOfTheWrittenModel) {
  TemporaryFolder out;
  const auto result = run_isospring("calibrate " + example("calibrate_square.json") + " -o " +
                                    out.path().string() + " --quiet");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_EQ(result.output, "");  // --quiet

  const json report = read_json(out / "report.json");
  EXPECT_EQ(report["command"], "calibrate");
  EXPECT_EQ(report["springs"], 110);  // published count of a 6 x 6 net [S15]
  EXPECT_EQ(report["particles"], 36);
  const int groups = report["groups"];
  EXPECT_EQ(groups, 110);  // one stiffness per spring
  EXPECT_EQ(report["per_spring"], true);
  ASSERT_EQ(report["fit"]["load_cases"].size(), 3u);
  ASSERT_EQ(report["holdout"]["load_cases"].size(), 1u);
  EXPECT_EQ(report["holdout"]["load_cases"][0]["id"], "v1_x");

  const isospring::io::SpringModel model = isospring::io::read_model_json(out / "model.json");
  const auto& net = model.network;
  ASSERT_EQ(net.springs.size(), 110u);
  std::map<int, double> k_of_group;
  for (const auto& s : net.springs) {
    EXPECT_GT(s.stiffness, 0.0);
    EXPECT_GT(s.damping, 0.0);  // damping_alpha 200
    ASSERT_GE(s.group, 0);
    ASSERT_LT(s.group, groups);
    EXPECT_EQ(k_of_group.count(s.group), 0u);  // per spring: every group once
    k_of_group[s.group] = s.stiffness;
  }
  int fixed = 0;
  for (bool f : net.fixed) fixed += f;
  EXPECT_EQ(fixed, 6);  // side u0 of the 6 x 6 net

  // The errors the report claims are those of the written model, to round-off.
  const isospring::io::Case c = isospring::io::read_case_file(example("calibrate_square.json"));
  for (const json& lc : report["fit"]["load_cases"])
    EXPECT_NEAR(recomputed_e_rms(c, net, lc["id"]), lc["percent_e_rms"].get<double>(), 1e-9);
  const json& held = report["holdout"]["load_cases"][0];
  EXPECT_NEAR(recomputed_e_rms(c, net, "v1_x"), held["percent_e_rms"].get<double>(), 1e-9);
  // Measured 1.47% over the three fitted cases and 3.13% on the held-out one (a grouped fit of
  // the same cases: 8.9% / 10.3%). [S15 Table 5.3] reports 1.14% for ONE fitted case.
  EXPECT_LT(report["percent_e_rms"].get<double>(), 2.0);
  EXPECT_LT(held["percent_e_rms"].get<double>(), 4.0);

  // The matrix approach is reported beside it.
  ASSERT_GE(report["matrix_approach"].size(), 1u);
  const json& matrix = report["matrix_approach"][0];
  EXPECT_EQ(matrix["method"], "global");
  EXPECT_GT(matrix["relative_frobenius_residual"].get<double>(), 0.0);
  EXPECT_LT(matrix["relative_frobenius_residual"].get<double>(), 1.0);

  // Error table: one row per control point, error = |(ex, ey, ez)|.
  std::ifstream csv(out / "v1_x_errors.csv");
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "node,x,y,z,ex,ey,ez,error");
  int rows = 0;
  while (std::getline(csv, line)) ++rows;
  EXPECT_EQ(rows, 36);
  EXPECT_TRUE(std::filesystem::exists(out / "report.md"));
  EXPECT_TRUE(std::filesystem::exists(out / "springs.vtp"));
}

// progress a person can read. Not on a terminal (a pipe here): milestone lines only,
// no line per fit iteration. On a terminal (a pseudo-terminal from util-linux `script`): the
// iterations rewrite one status line (carriage return, clear line) with stage, iteration, cost
// and elapsed time, which the next milestone replaces.
TEST(Calibrate, ProgressIsMilestonesInLogsAndOneUpdatingLineOnATerminal) {
  TemporaryFolder out;
  const std::string command =
      "calibrate " + example("calibrate_square.json") + " -o " + out.path().string();
  const auto result = run_isospring(command);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_EQ(result.output.find("iteration"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("[calibrate] reading "), std::string::npos) << result.output;
  EXPECT_LE(std::count(result.output.begin(), result.output.end(), '\n'), 10) << result.output;

  if (std::system("command -v script > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "util-linux `script` not found: the terminal display is not checked";
  const auto tty = isospring::testing::run_program(
      "script -qec '" + std::string(ISOSPRING_EXECUTABLE) + " calibrate " +
      example("calibrate_square.json") + " -o " + (out / "tty") + "' /dev/null");
  ASSERT_EQ(tty.exit_code, 0) << tty.output;
  const std::regex status(
      "\r\033\\[K\\[calibrate\\] fit \\(gamma 0\\.01\\): iteration [0-9]+, "
      "cost [-0-9.e+]+, [0-9.]+ s");
  EXPECT_TRUE(std::regex_search(tty.output, status)) << tty.output;
  // No status line is left behind: each is cleared before the next milestone line.
  EXPECT_EQ(tty.output.find(" s\n"), std::string::npos) << tty.output;
  EXPECT_EQ(tty.output.find(" s\r\n"), std::string::npos) << tty.output;
}

TEST(Calibrate, UnknownCalibrationFieldIsBadInput) {
  TemporaryFolder out;
  json c = read_json(example("calibrate_square.json"));
  c["calibration"]["gama"] = 0.1;
  std::ofstream(out / "case.json") << c.dump();
  const auto result =
      run_isospring("calibrate " + (out / "case.json") + " -o " + (out / "result") + " --quiet");
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_NE(result.output.find("calibration.gama: unknown field"), std::string::npos)
      << result.output;
}

TEST(Calibrate, NonConvergenceExitsWithThreeAndWritesNoModel) {
  TemporaryFolder out;
  json c = read_json(example("calibrate_square.json"));
  c["calibration"]["max_iterations"] = 1;
  std::ofstream(out / "case.json") << c.dump();
  const auto result =
      run_isospring("calibrate " + (out / "case.json") + " -o " + (out / "result") + " --quiet");
  EXPECT_EQ(result.exit_code, 3) << result.output;
  EXPECT_NE(result.output.find("did not converge"), std::string::npos) << result.output;
  EXPECT_FALSE(std::filesystem::exists(out / "result/model.json"));
}

// damping_ratio reaches the written model: every spring's c is zeta times its critical damping
// (the free particle's mass when the other end is held, else the reduced mass; the meaning of
// zeta is tested against the logarithmic decrement in tests/analysis). Giving damping_alpha as
// well is bad input.
TEST(Calibrate, DampingRatioIsCarriedIntoTheModel) {
  TemporaryFolder out;
  json c = read_json(example("calibrate_square.json"));
  c["calibration"].erase("damping_alpha");
  c["calibration"]["damping_ratio"] = 0.05;
  c["calibration"]["acceleration_objective"] = false;
  std::ofstream(out / "case.json") << c.dump();
  auto result =
      run_isospring("calibrate " + (out / "case.json") + " -o " + (out / "result") + " --quiet");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const auto model = isospring::io::read_model_json(out / "result/model.json");
  const auto& net = model.network;
  for (const auto& s : net.springs) {
    const double mi = net.masses[s.i], mj = net.masses[s.j];
    // One end held: the other particle's mass; both or neither: the reduced mass (a spring
    // between two held particles never moves, its damping is immaterial).
    const bool one_held = net.fixed[s.i] != net.fixed[s.j];
    const double m = one_held ? (net.fixed[s.i] ? mj : mi) : mi * mj / (mi + mj);
    EXPECT_NEAR(s.damping, 2 * 0.05 * std::sqrt(s.stiffness * m), 1e-12 * s.damping);
  }
  EXPECT_TRUE(read_json(out / "result/report.json")["acceleration_objective"].is_null());
  EXPECT_EQ(read_json(out / "result/model.json")["provenance"]["damping"], json({{"ratio", 0.05}}));

  c["calibration"]["damping_alpha"] = 200;
  std::ofstream(out / "both.json") << c.dump();
  result = run_isospring("calibrate " + (out / "both.json") + " -o " + (out / "both") + " -q");
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_NE(result.output.find("damping_ratio: give damping_alpha"), std::string::npos)
      << result.output;
}

// The acceleration objective [S15 4.1-4.5] is reported beside the displacement fit on the rest-
// length grouping the per-spring fit started from (gamma 0.01: 5 groups on this net), with its
// errors on the fitted and held-out cases. The displacement objective is what it minimises, so
// the displacement fit's %e_rms must be lower than the baseline's on the fitted cases.
TEST(Calibrate, ReportsTheAccelerationObjectiveBaseline) {
  TemporaryFolder out;
  const auto result = run_isospring("calibrate " + example("calibrate_square.json") + " -o " +
                                    (out / "result") + " -q");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const json report = read_json(out / "result/report.json");
  const json& a = report["acceleration_objective"];
  ASSERT_TRUE(a.is_object()) << report.dump(2);
  EXPECT_EQ(a["groups"], 5);
  EXPECT_GT(a["relative_residual"].get<double>(), 0.0);
  ASSERT_TRUE(a["fit"].is_object());
  EXPECT_EQ(a["fit"]["load_cases"].size(), 3u);
  EXPECT_EQ(a["holdout"]["load_cases"].size(), 1u);
  EXPECT_LT(report["percent_e_rms"].get<double>(), a["fit"]["percent_e_rms"].get<double>());
  // A membrane is its own surface: the surface metric is the field metric, exactly.
  for (const char* part : {"fit", "holdout"})
    for (const json& e : report[part]["load_cases"]) {
      EXPECT_EQ(e["surface_percent_e_rms"], e["field_percent_e_rms"]) << e.dump();
      EXPECT_EQ(e["surface_percent_e_max"], e["field_percent_e_max"]) << e.dump();
    }
  EXPECT_EQ(read_json(out / "result/model.json")["provenance"]["damping"], json({{"alpha", 200}}));
}

// The surface metric of a volume, end to end on a small cantilever box. With 2 samples per
// direction every sample is a corner of the box, so the surface and the field metrics sample the
// same 8 points and must agree exactly; with 5 the field adds 27 interior points and the two
// differ (the error inside the box is not the error on its surface).
TEST(Calibrate, SurfaceMetricOfAVolume) {
  TemporaryFolder out;
  json c = read_json(example("cantilever_box.json"));
  c["discretization"]["elements"] = {3, 1, 1};
  c["load_cases"].erase(2);  // gravity: two traction cases suffice
  c["calibration"] = {{"grouping", {{"gamma", 0.01}}},
                      {"matrix_approach", false},
                      {"acceleration_objective", false}};
  std::map<int, json> cases;
  for (int samples : {2, 5}) {
    c["calibration"]["field_samples"] = samples;
    const std::string name = "box" + std::to_string(samples);
    std::ofstream(out / (name + ".json")) << c.dump();
    const auto result =
        run_isospring("calibrate " + (out / (name + ".json")) + " -o " + (out / name) + " -q");
    ASSERT_EQ(result.exit_code, 0) << result.output;
    cases[samples] = read_json(out / (name + "/report.json"))["fit"]["load_cases"];
    ASSERT_EQ(cases[samples].size(), 2u);
  }
  for (const json& e : cases[2]) {
    EXPECT_GT(e["surface_percent_e_rms"].get<double>(), 0.0) << e.dump();
    EXPECT_EQ(e["surface_percent_e_rms"], e["field_percent_e_rms"]) << e.dump();
    EXPECT_EQ(e["surface_percent_e_max"], e["field_percent_e_max"]) << e.dump();
  }
  for (const json& e : cases[5])
    EXPECT_NE(e["surface_percent_e_rms"], e["field_percent_e_rms"]) << e.dump();
}

// calibration.generalisation: the load suite is fitted, the case's own four load
// cases are held out; every held-out error the report claims is that of the written model
// (recomputed here against a fresh IGA reference), the worst is the largest over all cases, and
// a worst case above target_percent_e_rms is a warning, not a quiet export.
TEST(Calibrate, GeneralisedSquareReportsEveryHeldOutCaseAndFlagsTheTarget) {
  TemporaryFolder out;
  const auto result = run_isospring("calibrate " + example("calibrate_square_generalised.json") +
                                    " -o " + out.path().string() + " --quiet");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const json report = read_json(out / "report.json");
  const isospring::io::Case c =
      isospring::io::read_case_file(example("calibrate_square_generalised.json"));
  const isospring::io::SpringModel model = isospring::io::read_model_json(out / "model.json");
  double worst = 0.0;
  int own = 0;
  for (const char* part : {"fit", "holdout"})
    for (const json& lc : report[part]["load_cases"]) {
      worst = std::max(worst, lc["percent_e_rms"].get<double>());
      for (const auto& own_case : c.problem.load_cases)
        if (own_case.id == lc["id"]) {
          EXPECT_EQ(std::string(part), "holdout") << own_case.id << " must not be fitted";
          EXPECT_NEAR(recomputed_e_rms(c, model.network, own_case.id),
                      lc["percent_e_rms"].get<double>(), 1e-9);
          // Never fitted, yet within [S15]'s published fitted-case error of this square x 2.
          EXPECT_LT(lc["percent_e_rms"].get<double>(), 2.0 * 1.14) << own_case.id;
          ++own;
        }
    }
  EXPECT_EQ(own, 4);
  EXPECT_DOUBLE_EQ(report["worst_percent_e_rms"].get<double>(), worst);
  ASSERT_TRUE(report["generalisation"].is_object());
  EXPECT_FALSE(report["generalisation"]["candidates"].empty());
  const bool meets = worst <= report["target_percent_e_rms"].get<double>();
  EXPECT_EQ(report["meets_target"].get<bool>(), meets);
  bool warned = false;
  for (const json& w : report["warnings"])
    warned = warned || w.get<std::string>().find("exceeds") != std::string::npos;
  EXPECT_EQ(warned, !meets);
}
