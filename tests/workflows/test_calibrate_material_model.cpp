// `calibrate` with a finite-strain material.model calibrates at large deformation and needs the
// amplitudes to fit at: without calibration.amplitudes it is refused naming that field, never
// calibrated linearly in silence.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include "isospring/io/case_file.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/workflows/calibrate_command.hpp"

namespace isospring::workflows {
namespace {

TEST(CalibrateMaterialModel, FiniteStrainModelWithoutAmplitudesIsRefusedNamingTheField) {
  std::ifstream in(std::string(ISOSPRING_SOURCE_DIR) + "/examples/calibrate_square.json");
  nlohmann::json document = nlohmann::json::parse(in);
  document["analysis"]["type"] = "plane_strain";
  document["material"]["model"] = "neo_hookean";
  document["calibration"].erase("grouping");
  document["calibration"].erase("regularization");
  document["calibration"].erase("matrix_approach");
  const io::Case c = io::build_case_from_json(document, "case.json");
  try {
    run_calibrate(c, io::Progress("calibrate", true));
    ADD_FAILURE() << "a neo-Hookean case was calibrated linearly";
  } catch (const nurbs::InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("case.json: calibration.amplitudes: material.model", 0),
              0u)
        << e.what();
  }
}

}  // namespace
}  // namespace isospring::workflows
