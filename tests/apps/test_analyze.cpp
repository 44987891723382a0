// End-to-end: `isospring analyze` on shipped case files. Checks against independent facts:
// the Timoshenko cantilever's exact (cubic) solution, static equilibrium of the reactions with
// the applied loads, consistency of report.json and the CSV tables, and the exit codes.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <utility>

#include "run_program.hpp"

using isospring::testing::example;
using isospring::testing::read_json;
using isospring::testing::run_isospring;
using isospring::testing::run_isospring_with_environment;
using isospring::testing::TemporaryFolder;
using nlohmann::json;

namespace {
/// Rows of a control-displacement table: i, x, y, z, ux, uy, uz.
std::vector<std::array<double, 7>> read_table(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "i,x,y,z,ux,uy,uz");
  std::vector<std::array<double, 7>> rows;
  while (std::getline(in, line)) {
    std::array<double, 7> row{};
    std::stringstream fields(line);
    std::string cell;
    for (double& value : row) {
      std::getline(fields, cell, ',');
      value = std::stod(cell);
    }
    rows.push_back(row);
  }
  return rows;
}
}  // namespace

TEST(Analyze, TimoshenkoBeamReproducesTheCubicExactSolution) {
  // The exact solution is a cubic polynomial, so cubic IGA with the exact clamp (projected) and
  // the exact end traction reproduces it up to the solver's round-off; the corner control points
  // interpolate the displacement.
  TemporaryFolder out;
  const auto result = run_isospring("analyze " + example("timoshenko_beam.json") + " -o " +
                                    out.path().string() + " --quiet");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_EQ(result.output, "");  // --quiet
  const double E = 1e5, nu = 0.3, L = 10, D = 2, P = 1, I = D * D * D / 12;
  const double tip = -P / (6 * E * I) * ((4 + 5 * nu) * D * D * L / 4 + 2 * L * L * L);
  int corners = 0;
  for (const auto& row : read_table(out / "end_shear_control_displacements.csv")) {
    if (row[1] != L || (row[2] != 0 && row[2] != D)) continue;
    ++corners;
    EXPECT_NEAR(row[5], tip, 1e-9 * std::abs(tip));
    const double y = row[2] - D / 2;
    EXPECT_NEAR(row[4], P * y / (6 * E * I) * 3 * L * L, 1e-9 * std::abs(tip));
  }
  EXPECT_EQ(corners, 2);
}

TEST(Analyze, CantileverReactionsBalanceTheLoadsAndTablesMatchTheReport) {
  TemporaryFolder out;
  const auto result =
      run_isospring("analyze " + example("cantilever_box.json") + " -o " + out.path().string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("[analyze] load case tip_down (1/3)"), std::string::npos);

  const json report = read_json(out / "report.json");
  EXPECT_EQ(report["command"], "analyze");
  EXPECT_EQ(report["case"]["name"], "cantilever_box");
  EXPECT_EQ(report["dofs"], 3 * 22 * 6 * 6);
  // --solver auto (the default) takes the direct solver at this size and says why.
  EXPECT_EQ(report["solver"], "cholesky");
  EXPECT_EQ(report["solver_requested"], "auto");
  EXPECT_NE(report["solver_reason"].get<std::string>().find("sparse Cholesky"), std::string::npos)
      << report["solver_reason"];
  ASSERT_EQ(report["load_cases"].size(), 3u);
  // Applied: traction 100 Pa on 0.02 x 0.02 m; 50 Pa sideways; weight 1100 * 9.81 * volume.
  const double area = 0.02 * 0.02, volume = 0.1 * area;
  const std::array<std::array<double, 3>, 3> applied{
      {{0, 0, -100 * area}, {0, 50 * area, 0}, {0, 0, -1100 * 9.81 * volume}}};
  for (size_t k = 0; k < 3; ++k) {
    const json& lc = report["load_cases"][k];
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(lc["reaction_sum"][c].get<double>(), -applied[k][c], 1e-10)
          << lc["id"] << " component " << c;
    EXPECT_GT(lc["strain_energy"].get<double>(), 0);
    const auto rows = read_table(out / lc["control_displacements_file"].get<std::string>());
    ASSERT_EQ(rows.size(), 22u * 6 * 6);
    double max_u = 0;
    for (const auto& row : rows) max_u = std::max(max_u, std::hypot(row[4], row[5], row[6]));
    EXPECT_DOUBLE_EQ(max_u, lc["max_displacement"].get<double>());
  }
  // Linear elasticity: the energy of the sideways load (half the traction) relates to the
  // downward one through the square-section symmetry: same stiffness, so a quarter.
  EXPECT_NEAR(report["load_cases"][1]["strain_energy"].get<double>(),
              report["load_cases"][0]["strain_energy"].get<double>() / 4, 1e-12);
  std::ifstream md(out / "report.md");
  std::stringstream text;
  text << md.rdbuf();
  EXPECT_NE(text.str().find("| tip_down |"), std::string::npos);
  // The BLAS behind CHOLMOD, as the program loaded it.
  const std::string blas = report["blas"]["name"].get<std::string>();
  EXPECT_FALSE(blas.empty());
  EXPECT_TRUE(std::filesystem::exists(report["blas"]["library"].get<std::string>()));
  EXPECT_NE(text.str().find("BLAS/LAPACK: " + blas), std::string::npos);
}

TEST(Analyze, ConjugateGradientsReportIterationsAndAgreeWithTheDefault) {
  TemporaryFolder direct, iterative;
  for (const auto& [out, flag] : {std::pair{&direct, ""}, std::pair{&iterative, " --solver cg"}}) {
    const auto result = run_isospring("analyze " + example("cantilever_box.json") + " -o " +
                                      out->path().string() + " --quiet" + flag);
    ASSERT_EQ(result.exit_code, 0) << result.output;
  }
  const json a = read_json(direct / "report.json"), b = read_json(iterative / "report.json");
  EXPECT_EQ(b["solver"], "cg");
  EXPECT_FALSE(b.contains("solver_reason"));  // chosen by the user
  EXPECT_FALSE(a["load_cases"][0].contains("iterations"));
  for (size_t k = 0; k < 3; ++k) {
    const json& lc = b["load_cases"][k];
    EXPECT_GT(lc["iterations"].get<int>(), 0);
    EXPECT_LT(lc["relative_residual"].get<double>(), 1e-9);
    const double max_u = a["load_cases"][k]["max_displacement"].get<double>();
    EXPECT_NEAR(lc["max_displacement"].get<double>(), max_u, 1e-8 * max_u);
  }
}

TEST(Analyze, ReportsTheBlasThatTheDynamicLinkerChose) {
  // Debian installs each BLAS as libblas.so.3 in its own folder; LD_LIBRARY_PATH picks one for a
  // run whatever the alternatives system points to, and the report must follow.
  const std::string lib = "/usr/lib/x86_64-linux-gnu/";
  int checked = 0;
  for (const auto& [folder, name] :
       {std::pair{"openblas-pthread", "OpenBLAS"}, std::pair{"atlas", "ATLAS"},
        std::pair{"blas", "reference BLAS"}}) {
    if (!std::filesystem::exists(lib + folder + "/libblas.so.3")) continue;
    ++checked;
    TemporaryFolder out;
    const auto result = run_isospring_with_environment(
        "env LD_LIBRARY_PATH=" + lib + folder,
        "analyze " + example("timoshenko_beam.json") + " -o " + out.path().string() + " --quiet");
    ASSERT_EQ(result.exit_code, 0) << result.output;
    const json report = read_json(out / "report.json");
    EXPECT_EQ(report["blas"]["name"], name) << report["blas"].dump();
    EXPECT_EQ(report["blas"]["library"].get<std::string>().find(lib + folder + "/"), 0u)
        << report["blas"].dump();
  }
  if (checked == 0) GTEST_SKIP() << "no Debian BLAS folder in " << lib;
}

TEST(Analyze, BadInputExitsWithOneAndNamesTheField) {
  TemporaryFolder folder;
  json doc = read_json(example("cantilever_box.json"));
  const std::vector<std::pair<std::function<void(json&)>, std::string>> cases{
      {[](json& d) { d["load_cases"][0]["traction"] = d["load_cases"][0]["tractions"]; },
       "case.json: load_cases[0].traction: unknown field; did you mean 'tractions'?"},
      {[](json& d) { d["material"]["nu"] = 0.5; }, "case.json: material.nu must be in (-1, 0.5)"},
      {[](json& d) { d["material"]["E"] = -1.0; }, "case.json: material.E must be > 0"},
      {[](json& d) { d["units"] = "mm"; }, "case.json: units: 'mm' is not supported"},
      {[](json& d) { d["boundary"][0]["side"] = "w7"; }, "case.json: boundary[0].side"},
      {[](json& d) { d["load_cases"][1]["id"] = "tip_down"; }, "is used twice"},
      {[](json& d) { d["load_cases"][0]["tractions"][0]["side"] = "u0"; }, "is fully fixed"},
      {[](json& d) { d["load_cases"][2].erase("gravity"); }, "has no load"},
      {[](json& d) {
         d["measurements"] = {{"file", "nowhere.csv"}};
       },
       "case.json: measurements.file: 'nowhere.csv' does not exist"},
      {[](json& d) { d.erase("boundary"); }, "case.json: boundary is missing"},
  };
  for (const auto& [edit, expected] : cases) {
    json bad = doc;
    edit(bad);
    std::ofstream(folder / "case.json") << bad.dump(2);
    const auto result = run_isospring("analyze " + folder / "case.json" + " -o " + folder / "out");
    EXPECT_EQ(result.exit_code, 1) << expected << "\n" << result.output;
    EXPECT_NE(result.output.find(expected), std::string::npos) << result.output;
  }
  std::ofstream(folder / "broken.json") << "{\"name\": ";
  EXPECT_EQ(run_isospring("analyze " + folder / "broken.json" + " -o " + folder / "out").exit_code,
            1);
  // Usage errors: no output folder, unknown solver.
  EXPECT_EQ(run_isospring("analyze " + example("cantilever_box.json")).exit_code, 2);
  EXPECT_EQ(run_isospring("analyze " + example("cantilever_box.json") + " -o " + folder / "o" +
                          " --solver lu")
                .exit_code,
            2);
  EXPECT_FALSE(std::filesystem::exists(folder / "out"));  // nothing written on bad input
}
