// `isospring info FILE`: what a patch file, a case file or a CAD part holds: per patch its
// dimensions, degrees, knot vectors (unique knots with multiplicities), control points, elements,
// bounding box and length/area/volume; for a case file also its material, supports and loads; for
// a CAD part OpenCascade's own report (units, faces, volume and area). The text and the JSON
// are the library's (isospring/workflows/info_command.hpp).
#include <iostream>
#include <memory>

#include "command.hpp"
#include "isospring/workflows/info_command.hpp"

namespace isospring::apps {
namespace {

void setup_info(CLI::App& app) {
  auto file = std::make_shared<std::string>();
  auto json = std::make_shared<bool>(false);
  CLI::App* cmd = app.add_subcommand(
      "info",
      "Describe a patch file, case file or STEP/IGES part: patches, degrees, knots, "
      "control points, elements, size");
  cmd->add_option("FILE", *file, "Patch file or case file (.json), or CAD part (.step/.iges)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_flag("--json", *json,
                "Print JSON instead (patches with degrees, control points, elements, bounds, "
                "measure; case or CAD summary), full precision");
  cmd->callback([file, json] {
    if (*json)
      std::cout << workflows::file_info_json(*file).dump(2) << "\n";
    else
      std::cout << workflows::file_info_text(*file);
  });
}

}  // namespace
ISOSPRING_REGISTER_COMMAND(10, setup_info);
}  // namespace isospring::apps
