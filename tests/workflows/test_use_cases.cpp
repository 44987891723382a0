// The commands' use cases as library calls (io/analyze_command.hpp, identify_command.hpp,
// calibrate_command.hpp, study_command.hpp) on shipped cases: results, reports and files without
// running the program. tests/apps checks the same runs through `isospring`, with their numbers.
#include <gtest/gtest.h>
#include <unistd.h>  // getpid: CTest runs tests in parallel processes

#include <filesystem>
#include <fstream>

#include "isospring/nurbs/error.hpp"
#include "isospring/workflows/analyze_command.hpp"
#include "isospring/workflows/calibrate_command.hpp"
#include "isospring/workflows/identify_command.hpp"
#include "isospring/workflows/study_command.hpp"

namespace isospring::workflows {
using namespace isospring::io;  // the formats the use cases read and write
namespace {
namespace fs = std::filesystem;

const std::string kExamples = std::string(ISOSPRING_SOURCE_DIR) + "/examples/";

fs::path fresh_folder(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("isospring_use_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  return dir;
}

nlohmann::json read_json(const fs::path& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

TEST(AnalyzeUseCase, SolvesTheBoxAndWritesEveryOutput) {
  AnalyzeCommandOptions options;
  options.case_file = kExamples + "cantilever_box.json";
  options.vtk_samples = 2;
  const Progress progress("analyze", true);
  int checked = 0;
  const AnalyzeCommandResult r =
      run_analyze(options, progress, [&](const Case& c) { checked = c.problem.load_cases.size(); });
  ASSERT_EQ(checked, 3);  // the hook saw the case before the solve
  ASSERT_EQ(r.result.load_cases.size(), 3u);
  const fs::path out = fresh_folder("analyze");
  fs::create_directories(out);
  const nlohmann::json report =
      write_analyze_outputs(r, options, out, progress, std::chrono::steady_clock::now());
  EXPECT_EQ(report["dofs"], r.result.dofs);
  EXPECT_EQ(report["load_cases"].size(), 3u);
  EXPECT_EQ(read_json(out / "report.json")["load_cases"][0]["max_displacement"],
            r.result.load_cases[0].max_displacement);
  for (const std::string& csv : analyze_csv_names(r.c)) EXPECT_TRUE(fs::exists(out / csv)) << csv;
  EXPECT_TRUE(fs::exists(out / "result.vtm"));
  EXPECT_TRUE(fs::exists(out / "report.md"));
  fs::remove_all(out);
}

TEST(IdentifyUseCase, FindsTheHiddenGravityAndWritesTheReports) {
  const Case c = read_case_file(kExamples + "identify/plate_hidden_gravity.json");
  IdentifyCommandOptions options;
  options.discretization_check = false;  // the case's own mesh: fast, enough for gravity
  const Progress progress("identify", true);
  const IdentifyCommandResult r = run_identify(c, options, progress);
  EXPECT_EQ(r.markers.size() + r.dropped.size(), 196u);
  EXPECT_NE(std::find(r.identify.effects_added.begin(), r.identify.effects_added.end(), "gravity"),
            r.identify.effects_added.end());
  EXPECT_LT(r.identify.after.rms, r.identify.before.rms / 10);
  ASSERT_TRUE(r.recalibration.has_value()) << r.recalibration_error;

  const nlohmann::json report = identify_report_json(r);
  EXPECT_EQ(report["command"], "identify");
  EXPECT_EQ(report["markers"], r.markers.size());
  EXPECT_EQ(report["rms_after"], r.identify.after.rms);
  EXPECT_EQ(report["effects_added"], r.identify.effects_added);
  EXPECT_EQ(report["recalibration"]["model"], "model.json");
  const SpringModel model = identify_spring_model(r);
  EXPECT_EQ(model.load_cases.size(), 2u);
  EXPECT_EQ(model.gravity, r.recalibration->gravity);

  const fs::path out = fresh_folder("identify");
  write_identify_outputs(out, r, progress);
  for (const auto& name : identify_output_files(r.load_case_ids)) {
    if (name != "errors_before_after.png" && name != "residuals.gp") {  // gnuplot may be absent
      EXPECT_TRUE(fs::exists(out / name)) << name;
    }
  }
  EXPECT_EQ(read_json(out / "report.json")["rms_after"], r.identify.after.rms);
  fs::remove_all(out);
}

TEST(IdentifyUseCase, ACaseWithoutMeasurementsIsAnInputError) {
  const Case c = read_case_file(kExamples + "calibrate_square.json");
  try {
    run_identify(c, {}, Progress("identify", true));
    FAIL() << "no error";
  } catch (const nurbs::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("calibrate_square.json: no \"measurements\" object"),
              std::string::npos)
        << e.what();
  }
}

TEST(CalibrateUseCase, ReportAndModelMatchTheResult) {
  const Case c = read_case_file(kExamples + "calibrate_square.json");
  const Progress progress("calibrate", true);
  const CalibrateCommandResult r = run_calibrate(c, progress);
  ASSERT_EQ(r.calibration.fit.size(), 3u);
  ASSERT_EQ(r.calibration.holdout.size(), 1u);
  EXPECT_TRUE(r.request.settings.per_spring);
  EXPECT_EQ(r.worst_holdout, r.calibration.holdout[0].control.percent_e_rms);

  const nlohmann::json report = calibrate_report_json(r);
  EXPECT_EQ(report["command"], "calibrate");
  EXPECT_EQ(report["springs"], r.calibration.mesh.network.springs.size());
  EXPECT_EQ(report["holdout"]["load_cases"][0], case_errors_json(r.calibration.holdout[0]));
  EXPECT_EQ(report["worst_percent_e_rms"], r.worst);
  const SpringModel model = calibrate_spring_model(r, report);
  EXPECT_EQ(model.load_cases.size(), 4u);
  EXPECT_EQ(model.provenance["damping"]["alpha"], 200.0);

  const fs::path out = fresh_folder("calibrate");
  const nlohmann::json written = write_calibrate_outputs(out, r, std::chrono::steady_clock::now());
  EXPECT_EQ(written["percent_e_rms"], report["percent_e_rms"]);
  EXPECT_EQ(read_json(out / "report.json")["percent_e_rms"], report["percent_e_rms"]);
  for (const std::string name : {"model.json", "springs.vtp", "result.vtm", "u1_x_errors.csv"})
    EXPECT_TRUE(fs::exists(out / name)) << name;
  fs::remove_all(out);
}

// The gamma sweep's entries in report.json: the square has few distinct rest lengths, so gammas
// 0.01 and 0.05 give the same 5 groups (fitted once: identical numbers, reused_from_gamma), and
// 0.9 merges them into 2 groups with a larger error; the kept gamma is the best entry's.
TEST(CalibrateUseCase, GammaSweepEntriesInTheReport) {
  nlohmann::json document = read_json(kExamples + "calibrate_square.json");
  document["calibration"]["grouping"] = {{"gamma_sweep", {0.01, 0.05, 0.9}}};
  document["calibration"]["matrix_approach"] = false;
  document["calibration"].erase("regularization");  // per-spring fits only
  const fs::path folder = fresh_folder("calibrate_sweep");
  fs::create_directories(folder);
  std::ofstream(folder / "case.json") << document.dump(1);
  const CalibrateCommandResult r =
      run_calibrate(read_case_file(folder / "case.json"), Progress("calibrate", true));
  const nlohmann::json report = calibrate_report_json(r);
  const nlohmann::json& sweep = report["sweep"];
  ASSERT_EQ(sweep.size(), 3u);
  EXPECT_TRUE(sweep[0]["reused_from_gamma"].is_null());
  EXPECT_EQ(sweep[1]["reused_from_gamma"], 0.01);
  EXPECT_TRUE(sweep[2]["reused_from_gamma"].is_null());
  for (const char* key : {"groups", "parameters", "percent_e_rms", "percent_e_max"})
    EXPECT_EQ(sweep[1][key], sweep[0][key]) << key;
  EXPECT_GT(sweep[0]["groups"].get<int>(), sweep[2]["groups"].get<int>());
  EXPECT_GT(sweep[2]["percent_e_rms"].get<double>(), sweep[0]["percent_e_rms"].get<double>());
  for (const auto& entry : sweep) EXPECT_EQ(entry["failure"], "");
  EXPECT_EQ(r.calibration.gamma, 0.01);
  EXPECT_EQ(r.calibration.parameters, sweep[0]["parameters"].get<int>());
  fs::remove_all(folder);
}

TEST(StudyUseCase, TwoLevelsOfTheKirschPlate) {
  const Case c = read_case_file(kExamples + "kirsch_plate.json");
  StudyCommandOptions options;
  options.levels = 2;
  const Progress progress("study", true);
  const StudyCommandResult r = run_study(c, options, progress);
  ASSERT_EQ(r.rows.size(), 2u);
  EXPECT_TRUE(r.analytic());
  EXPECT_LT(r.rows[1].l2, r.rows[0].l2);  // refined: smaller error
  EXPECT_EQ(r.rows[1].elements, 2 * r.rows[0].elements);
  const StudyReport report = study_report(r);
  EXPECT_EQ(report.json["degrees"][0]["levels"].size(), 2u);
  EXPECT_EQ(report.csv.substr(0, report.csv.find('\n')),
            "degree,level,elements_u,dofs,h,relative_l2_error,relative_energy_error,quantity,"
            "quantity_error,assembly_seconds,factorization_seconds,solve_seconds");

  options.levels = 0;
  EXPECT_THROW(run_study(c, options, progress), nurbs::InputError);
  options.levels = 2;
  options.load_case = "nope";
  EXPECT_THROW(run_study(c, options, progress), nurbs::InputError);
}

}  // namespace
}  // namespace isospring::workflows
