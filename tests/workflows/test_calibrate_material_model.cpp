// `calibrate` fits linear references: a case whose material.model is finite-strain is refused
// with a message naming the field, never calibrated linearly in silence.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include "isospring/io/case_file.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/workflows/calibrate_command.hpp"

namespace isospring::workflows {
namespace {

TEST(CalibrateMaterialModel, FiniteStrainModelIsRefusedNamingTheField) {
  std::ifstream in(std::string(ISOSPRING_SOURCE_DIR) + "/examples/calibrate_square.json");
  nlohmann::json document = nlohmann::json::parse(in);
  document["analysis"]["type"] = "plane_strain";
  document["material"]["model"] = "neo_hookean";
  const io::Case c = io::build_case_from_json(document, "case.json");
  try {
    run_calibrate(c, io::Progress("calibrate", true));
    ADD_FAILURE() << "a neo-Hookean case was calibrated linearly";
  } catch (const nurbs::InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("case.json: material.model: the calibrate command", 0),
              0u)
        << e.what();
  }
}

}  // namespace
}  // namespace isospring::workflows
