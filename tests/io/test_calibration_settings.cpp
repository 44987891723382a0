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

TEST(CalibrationSettings, AmplitudesAreAListOrAMaximumWithSteps) {
  EXPECT_TRUE(read_calibration_settings(nullptr, "case.json").amplitudes.empty());
  EXPECT_EQ(
      read_calibration_settings(json::parse(R"({"amplitudes": [5, 20]})"), "case.json").amplitudes,
      (std::vector<double>{5.0, 20.0}));
  EXPECT_EQ(read_calibration_settings(json::parse(R"({"amplitudes": {"max": 20, "steps": 4}})"),
                                      "case.json")
                .amplitudes,
            (std::vector<double>{5.0, 10.0, 15.0, 20.0}));
  EXPECT_EQ(read_calibration_settings(json::parse(R"({"amplitudes": {"max": 7}})"), "case.json")
                .amplitudes,
            (std::vector<double>{7.0}));
  EXPECT_NE(error_of(json::parse(R"({"amplitudes": [20, 5]})")).find("amplitudes[1]"),
            std::string::npos);
  EXPECT_NE(error_of(json::parse(R"({"amplitudes": [0, 5]})")).find("amplitudes[0]"),
            std::string::npos);
  EXPECT_NE(error_of(json::parse(R"({"amplitudes": []})")).find("calibration.amplitudes"),
            std::string::npos);
  EXPECT_NE(error_of(json::parse(R"({"amplitudes": {"steps": 3}})")).find("amplitudes.max"),
            std::string::npos);
  EXPECT_NE(error_of(json::parse(R"({"amplitudes": {"max": 20, "steps": 0}})")).find("steps"),
            std::string::npos);
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
  // Types and ranges in the one wording of every io reader (case_json::Field).
  auto expect_message = [](const std::string& document, const std::string& message) {
    const std::string error = error_of(json::parse(document));
    EXPECT_NE(error.find(message), std::string::npos) << error;
  };
  expect_message("[1]", "case.json: calibration must be an object {...}, got array");
  expect_message(R"({"grouping": {"gamma": 1.5}})",
                 "case.json: calibration.grouping.gamma must be in [0, 1), got 1.5");
  expect_message(R"({"grouping": {"gamma_sweep": [0.1, -1]}})",
                 "case.json: calibration.grouping.gamma_sweep[1] must be in [0, 1), got -1");
  expect_message(R"({"damping_ratio": 0})", "case.json: calibration.damping_ratio must be > 0");
  expect_message(R"({"max_iterations": 0})",
                 "case.json: calibration.max_iterations must be an integer >= 1, got 0");
  expect_message(R"({"strain_points": 5})",
                 "case.json: calibration.strain_points must be an integer in [0, 4], got 5");
  expect_message(R"({"upper_bounds": "yes"})",
                 "case.json: calibration.upper_bounds must be true or false, got string");
  expect_message(R"({"generalisation": {"gammas": [2]}})",
                 "case.json: calibration.generalisation.gammas[0] must be in [0, 0.999], got 2");
  expect_message(R"({"generalisation": {"volume_terms": [1]}})",
                 "case.json: calibration.generalisation.volume_terms[0] must be true or false");
  expect_message(R"({"fit_load_cases": "L1"})",
                 "case.json: calibration.fit_load_cases: must be a list of load-case ids");
}

}  // namespace
}  // namespace isospring::io
