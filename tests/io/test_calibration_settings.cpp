// The case file's "calibration" object as typed settings (io/calibration_settings.hpp): defaults,
// values carried into fitting::CalibrationSettings, and bad fields named with the case file.
#include <gtest/gtest.h>

#include "isospring/io/calibration_settings.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::io {
namespace {
using nlohmann::json;

std::string error_of(const json& calibration) {
  try {
    read_calibration_settings(calibration, "case.json");
  } catch (const nurbs::InputError& e) {
    return e.what();
  }
  return "";
}

TEST(CalibrationSettings, AbsentObjectMeansTheDefaults) {
  const CalibrationRequest r = read_calibration_settings(nullptr, "case.json");
  const fitting::CalibrationSettings defaults;
  EXPECT_EQ(r.settings.gamma, defaults.gamma);
  EXPECT_FALSE(r.settings.per_spring);
  EXPECT_TRUE(r.matrix_approach);
  EXPECT_TRUE(r.acceleration_objective);
  EXPECT_FALSE(r.generalisation.has_value());
}

TEST(CalibrationSettings, FieldsAreCarriedOver) {
  const CalibrationRequest r = read_calibration_settings(
      json::parse(R"({"fit_load_cases": ["a", "b"], "holdout_load_cases": ["c"],
                      "grouping": {"per_spring": true, "gamma": 0.01}, "regularization": 1e-4,
                      "mass": "net_cells", "damping_alpha": 200, "max_iterations": 50})"),
      "case.json");
  EXPECT_EQ(r.settings.fit_cases, (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(r.settings.holdout_cases, (std::vector<std::string>{"c"}));
  EXPECT_TRUE(r.settings.per_spring);
  EXPECT_EQ(r.settings.gamma, 0.01);
  EXPECT_EQ(r.settings.regularization, 1e-4);
  EXPECT_EQ(r.settings.mass_model, fitting::MassModel::kNetCells);
  EXPECT_EQ(r.settings.damping_alpha, 200.0);
  EXPECT_EQ(r.settings.max_iterations, 50);
}

TEST(CalibrationSettings, GeneralisationDefaultsToTheLoadSuiteWithoutFitCases) {
  const CalibrationRequest r = read_calibration_settings(
      json::parse(R"({"generalisation": {"gammas": [0.5, 0.1], "folds": 4}})"), "case.json");
  ASSERT_TRUE(r.generalisation.has_value());
  EXPECT_TRUE(r.load_suite);
  EXPECT_EQ(r.generalisation->gammas, (std::vector<double>{0.5, 0.1}));
  EXPECT_EQ(r.generalisation->folds, 4);
}

TEST(CalibrationSettings, BadFieldsNameTheFileTheFieldAndTheFix) {
  EXPECT_NE(error_of(json::parse(R"({"gama": 0.1})")).find("case.json: calibration.gama: unknown"),
            std::string::npos);
  EXPECT_NE(error_of(json::parse(R"({"grouping": {"gamma": 0.1, "gamma_sweep": [0.1]}})"))
                .find("give either gamma or gamma_sweep"),
            std::string::npos);
  EXPECT_NE(error_of(json::parse(R"({"fit_load_cases": ["a"], "holdout_load_cases": ["a"]})"))
                .find("'a' is also in fit_load_cases"),
            std::string::npos);
  EXPECT_NE(error_of(json::parse(R"({"mass": "heavy"})")).find("calibration.mass: must be"),
            std::string::npos);
  EXPECT_NE(error_of(json::parse("[1]")).find("case.json: calibration: must be an object"),
            std::string::npos);
}

}  // namespace
}  // namespace isospring::io
