#pragma once
// The use case behind `isospring import PART.step -o patches.json`: a STEP/IGES part to NURBS
// patches (metres), with a triangulation of every face for display when asked, and the report
// of what the part held, what became patches, and for every face and solid that did not, why.
#include <cstddef>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "isospring/geometry/cad.hpp"
#include "isospring/io/report.hpp"
#include "isospring/nurbs/patch.hpp"

namespace isospring::workflows {

struct ImportCommandOptions {
  std::string input;          // the part (.step/.stp/.iges/.igs)
  double thickness = 0.0;     // > 0: extrude the (planar) faces along their normal [m]
  std::vector<int> faces;     // keep only these faces (empty: all)
  std::vector<int> solids;    // keep only these solids as volumes (excludes faces, thickness)
  std::string display;        // also write a triangulation of every face here (.vtp)
  double deflection = 1e-3;   // of the display triangulation, relative to the bbox diagonal
  bool print_report = false;  // print OpenCascade's per-face report
};

struct ImportCommandResult {
  geometry::CadModel model;
  std::vector<nurbs::Patch> patches;
  size_t display_triangles = 0;
};

/// Reads and converts the part; writes options.display when given. `report` gets the per-face
/// report when options.print_report, `log` the "wrote <display>" line (either may be null).
ImportCommandResult run_import(const ImportCommandOptions& options, std::ostream* report,
                               std::ostream* log);

/// The report's content beside the patch file `output` (FileReport's json and markdown).
void import_report(const ImportCommandResult& r, const ImportCommandOptions& options,
                   const std::string& output, nlohmann::json& json, io::MarkdownReport& md);

}  // namespace isospring::workflows
