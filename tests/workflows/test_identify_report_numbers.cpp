// The identification of the shipped example examples/identify/plate_hidden_gravity.json, run as
// `isospring identify` runs it, gives the report numbers it gave when they were recorded (the
// loop's stages were reorganised without changing any of them; recorded again when the fits
// learned to stop on an RSS decrease below 1e-3 residual variances, which moved E by 1e-3 of its
// standard error). Not bitwise: another CPU's BLAS
// kernels may round differently and the fit carries that on (two machines of the same kind gave
// gx 1.6e-12 of itself apart), so each number is held to 1e-9 of its recorded value; a change of
// the algorithm (an iteration more, a different weight or start) moves them by 1e-6 or more.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "isospring/io/case_file.hpp"
#include "isospring/io/report.hpp"
#include "isospring/workflows/identify_command.hpp"

namespace isospring::workflows {
namespace {

const std::string kExamples = std::string(ISOSPRING_SOURCE_DIR) + "/examples/";

void expect_recorded(double value, double recorded, const char* what) {
  EXPECT_LE(std::abs(value - recorded), 1e-9 * std::abs(recorded))
      << what << " = " << value << ", recorded " << recorded;
}

TEST(IdentifyReportNumbers, ShippedExampleKeepsItsRecordedNumbers) {
  const io::Case c = io::read_case_file(kExamples + "identify/plate_hidden_gravity.json");
  const IdentifyCommandResult r =
      run_identify(c, IdentifyCommandOptions{}, io::Progress("identify", true));
  const fitting::IdentifyResult& id = r.identify;
  ASSERT_EQ(id.effects_added, (std::vector<std::string>{"gravity", "rigid_offset_per_load"}));
  ASSERT_GE(id.parameters.size(), 3u);
  EXPECT_EQ(id.discretization.chosen, 1);
  EXPECT_EQ(id.holdout.validation_markers, 98);
  expect_recorded(id.before.rms, 2.6711979731139115e-05, "rms before");
  expect_recorded(id.after.rms, 9.5917386305257768e-07, "rms after");
  expect_recorded(id.noise_estimate, 9.8082781515234861e-07, "noise estimate");
  expect_recorded(id.chi2_before, 743.59406664916605, "chi2 before");
  expect_recorded(id.chi2_after, 0.97880553850068419, "chi2 after");
  expect_recorded(id.parameters[0].value, 1147739.4195292878, "E");
  expect_recorded(id.parameters[0].standard_error, 2158.8424274350809, "E's standard error");
  expect_recorded(id.parameters[1].value, -0.20368013844847255, "gx");
  expect_recorded(id.parameters[2].value, -9.896748629188254, "gy");
  expect_recorded(id.parameters[2].standard_error, 0.16269152861998723, "gy's standard error");
  expect_recorded(id.holdout.validation_after.rms, 9.8057439693381831e-07, "hold-out rms after");
}

}  // namespace
}  // namespace isospring::workflows
