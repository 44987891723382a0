// The refusals of commands without an immersed form (see immersed_refusals.hpp).
#include "isospring/workflows/immersed_refusals.hpp"

#include <fstream>
#include <nlohmann/json.hpp>

#include "isospring/io/immersed_case.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::workflows {
namespace {

/// Why `command` has no immersed form, and what to do instead.
std::string reason(const std::string& command) {
  if (command == "export-calculix")
    return "a CalculiX deck needs a mesh of the part, and an immersed model has none (its "
           "background cells are not the part's elements). For CalculiX, mesh the STEP file "
           "itself (e.g. with gmsh); for ParaView, `isospring analyze` writes the fields on the "
           "part (result.vtp)";
  if (command == "export-step")
    return "an immersed model's geometry is the CAD file itself, unchanged: use that file";
  return "it works on body-fitted patches only";
}

}  // namespace

void refuse_immersed_case(const std::filesystem::path& case_file, const std::string& command) {
  std::ifstream in(case_file);
  if (!in) return;
  const nlohmann::json document = nlohmann::json::parse(in, nullptr, false);
  if (document.is_discarded() || !io::is_immersed_case(document)) return;
  throw nurbs::InputError(
      case_file.string() + ": an immersed case (geometry type 'immersed'); `" + command +
      "` does not take one: " + reason(command) +
      ". `isospring analyze`, `study`, `calibrate` and `identify` run immersed cases.");
}

}  // namespace isospring::workflows
