// `calibrate --max-step-us`: a budget per engine step the calibration must keep (the case's
// calibration.max_step_us; fitting/step_cost.hpp). A plain calibration whose model is over it
// is refused with the estimate and the way out; the same budget in the case file is read the
// same; a generous one changes nothing.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "run_program.hpp"

using isospring::testing::example;
using isospring::testing::run_isospring;
using isospring::testing::TemporaryFolder;

TEST(CalibrateStepBudget, AModelOverTheBudgetIsRefusedAndOneWithinIsCalibrated) {
  TemporaryFolder out;
  auto run = run_isospring("calibrate " + example("calibrate_square.json") + " -o " +
                           (out / "tight") + " -q --max-step-us 0.001");
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_NE(run.output.find("max_step_us: the model"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("over the budget of 0.001 us"), std::string::npos) << run.output;

  std::ifstream in(example("calibrate_square.json"));
  nlohmann::json c = nlohmann::json::parse(in);
  c["calibration"]["max_step_us"] = 0.001;
  std::ofstream(out / "case.json") << c.dump();
  run = run_isospring("calibrate " + (out / "case.json") + " -o " + (out / "file") + " -q");
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_NE(run.output.find("max_step_us"), std::string::npos) << run.output;

  run = run_isospring("calibrate " + example("calibrate_square.json") + " -o " + (out / "ok") +
                      " -q --max-step-us 1000");
  EXPECT_EQ(run.exit_code, 0) << run.output;
}
