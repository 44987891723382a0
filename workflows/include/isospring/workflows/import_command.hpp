#pragma once
// The use case behind `isospring import PART.step -o OUT.json`: a STEP/IGES part to NURBS
// patches (metres), with a triangulation of every face for display when asked, and the report
// of what the part held, what became patches, and for every face and solid that did not, why.
// A solid that cannot become body-fitted volume patches takes the immersed path instead
// (import_immersed.hpp): OUT.json is then an immersed case file that `isospring analyze` runs,
// with the solid's faces listed for choosing supports and loads. The result says which path the
// part took and why.
#include <cstddef>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "isospring/geometry/cad.hpp"
#include "isospring/geometry/cad_face_selection.hpp"
#include "isospring/geometry/immersed_cad.hpp"
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
  /// "auto": body-fitted volume patches when every (chosen) solid becomes them, else the immersed
  /// path for the one solid that does not; "body-fitted": patches only (a solid that cannot be
  /// volumes gives its faces' patches or the face's error, as before the immersed path);
  /// "immersed": the immersed case of the solid even when body-fitted volumes exist.
  std::string path = "auto";
  /// Where the output goes: the immersed case names the part relative to this file's folder.
  std::string output;
};

struct ImportCommandResult {
  geometry::CadModel model;
  std::vector<nurbs::Patch> patches;  // body-fitted path only
  size_t display_triangles = 0;
  std::string path;         // "body-fitted" or "immersed"
  std::string path_reason;  // why, in a sentence
  /// Immersed path: the solid (0-based in the file), its faces, and the case file to write.
  int immersed_solid = -1;
  std::vector<geometry::SolidFace> faces;
  nlohmann::ordered_json immersed_case;
  double immersed_volume = 0.0;  // OpenCascade's, of the chosen solid (m^3)
  /// The solid's principal axes of inertia (geometry::principal_frame): the case's grid follows
  /// the file's axes, and "frame": "principal" would align it with these.
  geometry::PrincipalFrame principal;
};

/// Reads and converts the part; writes options.display when given. `report` gets the per-face
/// report when options.print_report, `log` the "wrote <display>" line (either may be null).
ImportCommandResult run_import(const ImportCommandOptions& options, std::ostream* report,
                               std::ostream* log);

/// The report's content beside the output file `output` (FileReport's json and markdown).
void import_report(const ImportCommandResult& r, const ImportCommandOptions& options,
                   const std::string& output, nlohmann::json& json, io::MarkdownReport& md);

}  // namespace isospring::workflows
