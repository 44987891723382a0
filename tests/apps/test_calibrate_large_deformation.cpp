// End-to-end: `isospring calibrate` on a plane-strain square with material.model neo_hookean and
// calibration.amplitudes runs the large-deformation calibration. Checked against what the
// report does not compute itself: the held-out error is recomputed from the written model.json
// (its springs' nonlinear equilibrium under the held-out load) against a fresh neo-Hookean IGA
// solve of the case file's held-out load; the per-amplitude rows agree with the per-case rows
// and the final cost; unsupported combinations are refused naming the field.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/dof_map.hpp"
#include "isospring/analysis/nonlinear_elasticity.hpp"
#include "isospring/fitting/nonlinear_displacement_fit.hpp"
#include "isospring/io/case_file.hpp"
#include "isospring/io/model_file.hpp"
#include "run_program.hpp"

using isospring::testing::read_json;
using isospring::testing::run_isospring;
using isospring::testing::TemporaryFolder;
using nlohmann::json;

namespace {

// A 10 cm square in plane strain (4 x 4 quadratic net), E = 15 kPa, clamped on x = 0: end
// stretch and bending fitted, a shear load on the top side held out (as given: about 12 %
// of %eps_G under the neo-Hookean law).
json square_case() {
  return {{"schema_version", 1},
          {"name", "large_square"},
          {"units", "SI"},
          {"geometry", {{"type", "square"}, {"size", 0.1}}},
          {"discretization", {{"degree", 2}, {"elements", {2, 2}}}},
          {"analysis", {{"type", "plane_strain"}}},
          {"material",
           {{"E", 15000.0}, {"nu", 1.0 / 3.0}, {"density", 1143.0}, {"model", "neo_hookean"}}},
          {"boundary", {{{"side", "u0"}, {"fix", {"x", "y"}}}}},
          {"load_cases",
           {{{"id", "u1_x"}, {"tractions", {{{"side", "u1"}, {"value", {1000.0, 0.0}}}}}},
            {{"id", "u1_y"}, {"tractions", {{{"side", "u1"}, {"value", {0.0, -300.0}}}}}},
            {{"id", "v1_x"}, {"tractions", {{{"side", "v1"}, {"value", {600.0, 0.0}}}}}}}},
          {"calibration",
           {{"fit_load_cases", {"u1_x", "u1_y"}},
            {"holdout_load_cases", {"v1_x"}},
            {"grouping", {{"gamma", 0.2}}},
            {"amplitudes", {2, 8}}}}};
}

}  // namespace

TEST(CalibrateLargeDeformation, HeldOutErrorIsTheWrittenModelsNonlinearEquilibrium) {
  TemporaryFolder out;
  std::ofstream(out / "case.json") << square_case().dump();
  const auto run =
      run_isospring("calibrate " + (out / "case.json") + " -o " + (out / "cal") + " -q");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const json report = read_json(out / "cal/report.json");
  const json& large = report["large_deformation"];
  ASSERT_TRUE(large.is_object()) << report.dump(1);
  EXPECT_EQ(large["law"], "neo_hookean");
  EXPECT_EQ(large["reached_amplitude"].get<double>(), 8.0) << large.dump(1);
  ASSERT_EQ(large["per_amplitude"].size(), 2u);
  ASSERT_EQ(report["fit"]["load_cases"].size(), 4u);  // two cases at two amplitudes

  // Per-amplitude rows are the per-case rows grouped by their "@amplitude"; the final cost is
  // half the sum of the squared fitted %e_rms / 100 (the objective the fit minimised).
  double cost = 0.0;
  for (const json& row : large["per_amplitude"]) {
    const std::string suffix = "@" + std::to_string(row["amplitude"].get<int>());
    double worst = 0.0;
    int cases = 0;
    for (const json& e : report["fit"]["load_cases"]) {
      const std::string id = e["id"];
      if (id.size() < suffix.size() || id.compare(id.size() - suffix.size(), suffix.size(), suffix))
        continue;
      worst = std::max(worst, e["percent_e_rms"].get<double>());
      cost += 0.5 * std::pow(e["percent_e_rms"].get<double>() / 100.0, 2);
      ++cases;
    }
    EXPECT_EQ(cases, 2) << suffix;
    EXPECT_DOUBLE_EQ(row["worst_percent_e_rms"].get<double>(), worst);
    // The reference's %eps_G is near its target (the scaling is by the LINEAR solution).
    EXPECT_NEAR(row["reference_percent_eps_g"].get<double>(), row["amplitude"].get<double>(),
                0.3 * row["amplitude"].get<double>());
  }
  EXPECT_NEAR(report["final_cost"].get<double>(), cost, 1e-6 * cost);

  // The held-out case from the files alone: model.json's springs at their nonlinear
  // equilibrium under the case's load (one patch, particle = control point), against a fresh
  // neo-Hookean solve.
  using namespace isospring;
  const io::SpringModel model = io::read_model_json(out / "cal/model.json");
  const io::Case c = io::read_case_file(out / "case.json");
  const analysis::DofMap dofs(c.problem);
  analysis::Problem held = c.problem;
  held.load_cases = {c.problem.load_cases[2]};
  analysis::NonlinearOptions options;
  options.material = analysis::HyperelasticMaterial::kNeoHookean;
  const Eigen::VectorXd u_ref = analysis::solve_static_nonlinear(held, options)[0].displacement;
  const Eigen::VectorXd f = analysis::assemble_load(held, dofs, held.load_cases[0]);
  ASSERT_EQ(f.size(), static_cast<Eigen::Index>(model.network.positions.size()) * 2);
  Eigen::VectorXd u;
  ASSERT_TRUE(fitting::spring_equilibrium(model.network, f, {}, u));
  double o_max = 0, sum = 0;
  for (int a = 0; a < dofs.num_nodes(); ++a) {
    o_max = std::max(o_max, u_ref.segment(2 * a, 2).norm());
    sum += (u.segment(2 * a, 2) - u_ref.segment(2 * a, 2)).squaredNorm();
  }
  const double recomputed = 100 * std::sqrt(sum / dofs.num_nodes()) / o_max;
  ASSERT_EQ(report["holdout"]["load_cases"].size(), 1u);
  EXPECT_NEAR(report["holdout"]["load_cases"][0]["percent_e_rms"].get<double>(), recomputed,
              1e-6 * recomputed);
  // The viewer and table files of every case, fitted ones by their scaled id.
  EXPECT_TRUE(std::filesystem::exists(out / "cal/u1_x@8_errors.csv"));
  EXPECT_TRUE(std::filesystem::exists(out / "cal/v1_x_errors.csv"));
  EXPECT_NE(isospring::testing::file_contents(out / "cal/report.md").find("per amplitude"),
            std::string::npos);
}

TEST(CalibrateLargeDeformation, UnsupportedCombinationsAreRefusedNamingTheField) {
  TemporaryFolder out;
  const std::vector<std::pair<std::string, json>> cases = {
      {"calibration.amplitudes",
       [] {
         json c = square_case();
         c["calibration"].erase("amplitudes");
         return c;
       }()},
      {"calibration.amplitudes",
       [] {
         json c = square_case();
         c["material"].erase("model");
         return c;
       }()},
      {"calibration.amplitudes[1]",
       [] {
         json c = square_case();
         c["calibration"]["amplitudes"] = {8, 2};
         return c;
       }()},
      {"calibration.matrix_approach",
       [] {
         json c = square_case();
         c["calibration"]["matrix_approach"] = true;
         return c;
       }()},
      {"calibration.grouping.per_spring",
       [] {
         json c = square_case();
         c["calibration"]["grouping"] = "per_spring";
         return c;
       }()},
  };
  int k = 0;
  for (const auto& [field, document] : cases) {
    const std::string file = out / ("bad" + std::to_string(k++) + ".json");
    std::ofstream(file) << document.dump();
    const auto run = run_isospring("calibrate " + file + " -o " + (out / "o") + " -q");
    EXPECT_EQ(run.exit_code, 1) << field << ": " << run.output;
    EXPECT_NE(run.output.find(field), std::string::npos) << run.output;
  }
}
