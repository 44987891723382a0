// End-to-end: immersed B-bar chosen by the case file's "analysis": {"volumetric": "bbar"} in
// `isospring analyze`, `study` and `calibrate`, on the shipped cylinder (examples/immersed) made
// nearly incompressible (nu = 0.49). The program's numbers are the library call's to 1e-12, its
// reports say which formulation ran, and a combination the immersed path does not have is
// refused with the field named and a non-zero exit. (The closed-form accuracy and rates are in
// tests/workflows/test_immersed_bbar_case.cpp, the Python module's agreement in
// tests/python/test_isospring.py.)
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "isospring/io/immersed_case.hpp"
#include "isospring/workflows/analyze_immersed.hpp"
#include "run_program.hpp"

using isospring::testing::example;
using isospring::testing::file_contents;
using isospring::testing::read_json;
using isospring::testing::run_isospring;
using isospring::testing::TemporaryFolder;
using nlohmann::json;

namespace {

// The shipped case at nu = 0.49 with `analysis` (none: the default), its CAD file by absolute
// path so that the copy runs from the temporary folder.
std::string write_case(const TemporaryFolder& out, const std::string& shipped,
                       const std::string& name, const json& analysis) {
  json c = read_json(example("immersed/" + shipped));
  c["geometry"]["file"] =
      std::filesystem::absolute(example("immersed/cube_cylinder.step")).string();
  c["material"]["nu"] = 0.49;
  if (!analysis.is_null()) c["analysis"] = analysis;
  const std::string file = out / name;
  std::ofstream(file) << c.dump(2);
  return file;
}

TEST(ImmersedBbarCli, AnalyzeAndStudyRunBbarAsTheLibraryDoes) {
  TemporaryFolder out;
  const std::string bbar_case =
      write_case(out, "cylinder_gravity.json", "bbar.json", {{"volumetric", "bbar"}});
  const std::string disp_case = write_case(out, "cylinder_gravity.json", "disp.json", nullptr);
  auto run = run_isospring("analyze " + bbar_case + " -o " + (out / "bbar") + " --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  run = run_isospring("analyze " + disp_case + " -o " + (out / "disp") + " --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const json bbar = read_json(out.path() / "bbar" / "report.json");
  const json disp = read_json(out.path() / "disp" / "report.json");
  EXPECT_EQ(bbar["volumetric"], "bbar");
  EXPECT_EQ(disp["volumetric"], "displacement");
  EXPECT_NE(file_contents(out / "bbar/report.md").find("B-bar"), std::string::npos);

  // The library call: the same numbers to 1e-12.
  using Method = isospring::analysis::SolverOptions::Method;
  const auto a = isospring::workflows::run_analyze_immersed(
      isospring::io::read_immersed_case(bbar_case), Method::kCholesky,
      isospring::io::Progress("analyze", true));
  ASSERT_EQ(a.load_cases.size(), 1u);
  const json& lc = bbar["load_cases"][0];
  const double w = lc["strain_energy"];
  EXPECT_NEAR(a.load_cases[0].result.strain_energy, w, 1e-12 * w);
  EXPECT_NEAR(a.load_cases[0].max_displacement, lc["max_displacement"].get<double>(),
              1e-12 * lc["max_displacement"].get<double>());
  // Locking stiffens the displacement formulation: under the same weight it stores less energy.
  const double w_disp = disp["load_cases"][0]["strain_energy"];
  std::printf("cylinder nu 0.49 under its weight: W bbar %.6e, displacement %.6e (ratio %.4f)\n", w,
              w_disp, w / w_disp);
  EXPECT_GT(w, w_disp);

  // study: level 0 is analyze's solve, with B-bar, and the report says so.
  run = run_isospring("study " + bbar_case + " -o " + (out / "study") + " --levels 1 --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const json study = read_json(out.path() / "study" / "report.json");
  EXPECT_EQ(study["case"]["volumetric"], "bbar");
  EXPECT_NEAR(study["degrees"][0]["levels"][0]["quantity"].get<double>(), w, 1e-9 * w);
  EXPECT_NE(file_contents(out / "study/report.md").find("B-bar"), std::string::npos);
}

TEST(ImmersedBbarCli, CalibrateReportsTheFormulationOfItsReferenceSolves) {
  TemporaryFolder out;
  const std::string file =
      write_case(out, "cylinder_calibrate.json", "cal.json", {{"volumetric", "bbar"}});
  const auto run = run_isospring("calibrate " + file + " -o " + (out / "cal") + " --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(read_json(out.path() / "cal" / "report.json")["volumetric"], "bbar");
  EXPECT_NE(file_contents(out / "cal/report.md").find("B-bar"), std::string::npos);
}

TEST(ImmersedBbarCli, UnsupportedCombinationsAreNamedErrors) {
  TemporaryFolder out;
  struct Bad {
    json analysis;
    std::string text;
  };
  for (const Bad& bad : {Bad{{{"type", "plane_stress"}, {"volumetric", "bbar"}},
                             "an immersed CAD part is a 3D solid"},
                         Bad{{{"volumetric", "mixed"}}, "unknown volumetric treatment 'mixed'"}}) {
    const std::string file = write_case(out, "cylinder_gravity.json", "bad.json", bad.analysis);
    const auto run = run_isospring("analyze " + file + " -o " + (out / "bad"));
    EXPECT_NE(run.exit_code, 0) << run.output;
    EXPECT_NE(run.output.find("bad.json"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("analysis"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find(bad.text), std::string::npos) << run.output;
    EXPECT_FALSE(std::filesystem::exists(out.path() / "bad" / "report.json"));
  }
}

}  // namespace
