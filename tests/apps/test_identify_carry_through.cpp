// `isospring identify` carries the identification through to the spring model: on the shipped
// example (hidden self-weight), the written model.json solved with the spring statics under its
// load cases INCLUDING the exported gravity forces m_i g reproduces an independent IGA solve of
// the corrected case (identified E and g) within the reported %e_rms; without the gravity forces
// it does not.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "isospring/analysis/spring_static.hpp"
#include "isospring/analysis/static_solver.hpp"
#include "isospring/fitting/error_metrics.hpp"
#include "isospring/io/case_file.hpp"
#include "isospring/io/model_file.hpp"
#include "run_program.hpp"

namespace isospring {
namespace {

const std::string kExample =
    std::string(ISOSPRING_SOURCE_DIR) + "/examples/identify/plate_hidden_gravity.json";

std::vector<Eigen::Vector3d> points(const Eigen::VectorXd& flat, int dim) {
  std::vector<Eigen::Vector3d> p(static_cast<size_t>(flat.size() / dim), Eigen::Vector3d::Zero());
  for (size_t a = 0; a < p.size(); ++a)
    p[a].head(dim) = flat.segment(static_cast<Eigen::Index>(a) * dim, dim);
  return p;
}

TEST(IdentifyCarryThrough, ExportedModelWithGravityReproducesTheCorrectedReference) {
  testing::TemporaryFolder out;
  const auto run =
      testing::run_isospring("identify " + kExample + " -o " + out.path().string() + " --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  std::ifstream file(out.path() / "report.json");
  const nlohmann::json report = nlohmann::json::parse(file);
  ASSERT_TRUE(report["recalibration"].contains("percent_e_rms")) << report["recalibration"];
  const io::SpringModel model = io::read_model_json(out.path() / "model.json");

  // The corrected case, built here from the case file and the reported parameters.
  analysis::Problem corrected = io::read_case_file(kExample).problem;
  Eigen::Vector3d g = Eigen::Vector3d::Zero();
  for (const auto& p : report["parameters"]) {
    if (p["name"] == "E") corrected.material.youngs_modulus = p["value"].get<double>();
    if (p["effect"] == "gravity") g[p["name"] == "gx" ? 0 : 1] = p["value"].get<double>();
  }
  ASSERT_GT(g.norm(), 9.0);  // the hidden self-weight was found (9.81 m/s^2 along -y)
  for (auto& load : corrected.load_cases) load.gravity = g;
  const analysis::StaticResult reference = analysis::solve_static(corrected);
  EXPECT_LT((model.gravity - g).norm(), 1e-12 * g.norm());

  const int dim = model.network.dimension;
  ASSERT_EQ(dim, 2);
  ASSERT_EQ(model.load_cases.size(), corrected.load_cases.size());
  for (size_t l = 0; l < corrected.load_cases.size(); ++l) {
    EXPECT_EQ(model.load_cases[l].id, corrected.load_cases[l].id);
    const Eigen::VectorXd& u_ref = reference.load_cases[l].displacement;
    // One patch: particle p is control point p.
    ASSERT_EQ(static_cast<Eigen::Index>(model.network.positions.size()) * dim, u_ref.size());
    const double reported = report["recalibration"]["load_cases"][l]["percent_e_rms"].get<double>();
    const auto with =
        analysis::solve_spring_linear(model.network, io::model_force_vector(model, l, true));
    const auto without =
        analysis::solve_spring_linear(model.network, io::model_force_vector(model, l, false));
    const double e_with =
        fitting::error_metrics(points(u_ref, dim), points(with.displacement, dim)).percent_e_rms;
    const double e_without =
        fitting::error_metrics(points(u_ref, dim), points(without.displacement, dim)).percent_e_rms;
    // Same loads as the fit and a reference equal to the identification's up to rounding: the
    // recomputed error matches the reported one to 1e-6 (JSON keeps full precision).
    EXPECT_LE(e_with, reported * (1.0 + 1e-6)) << corrected.load_cases[l].id;
    EXPECT_GT(e_with, 0.0);
    // Without the self-weight the model misses a deflection of the order of the load's own.
    EXPECT_GT(e_without, 5.0 * reported) << corrected.load_cases[l].id;
  }
  EXPECT_LT(report["recalibration"]["percent_e_rms"].get<double>(), 2.0);
}

TEST(IdentifyCarryThrough, RecalibrationFailureIsReportedNotFatal) {
  // Without a density the spring model has no masses: the identification still runs (gravity is
  // then unavailable), the recalibration's error is reported and model.json is not written.
  testing::TemporaryFolder out;
  const std::filesystem::path folder = out.path() / "case";
  std::filesystem::create_directories(folder);
  nlohmann::json c = nlohmann::json::parse(std::ifstream(kExample));
  c["material"].erase("density");
  std::ofstream(folder / "case.json") << c.dump();
  std::filesystem::copy_file(std::string(ISOSPRING_SOURCE_DIR) + "/examples/identify/markers.csv",
                             folder / "markers.csv");
  const auto run = testing::run_isospring("identify " + (folder / "case.json").string() + " -o " +
                                          (out.path() / "o").string() + " --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json report = nlohmann::json::parse(std::ifstream(out.path() / "o/report.json"));
  ASSERT_TRUE(report["recalibration"].contains("error"));
  EXPECT_NE(report["recalibration"]["error"].get<std::string>().find("density"), std::string::npos)
      << report["recalibration"];
  EXPECT_FALSE(std::filesystem::exists(out.path() / "o/model.json"));
}

}  // namespace
}  // namespace isospring
