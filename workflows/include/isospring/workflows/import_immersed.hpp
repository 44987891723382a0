#pragma once
// The immersed path of `isospring import`: which path a part takes, and the immersed case file
// written for a solid that cannot become body-fitted volume patches.
//
// The case is complete and runs as written (`isospring analyze OUT.json -o out`), but its
// support, load and material are placeholders stated in its "description": the largest planar
// face (else the largest face) clamped, the part's own weight along -z, steel. The solid's faces
// are listed under "faces" (index, surface type, STEP name, area, centroid, bounding box, a
// plane's outward normal, a cylinder's axis and radius) so that the user can replace them by the
// supports and loads the part has, by index or by selector (docs/case-files.md).
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "isospring/geometry/cad.hpp"
#include "isospring/geometry/cad_face_selection.hpp"
#include "isospring/io/report.hpp"
#include "isospring/workflows/import_command.hpp"

namespace isospring::workflows {

struct ImportPath {
  bool immersed = false;
  int solid = -1;  // immersed: the solid (0-based in the file; -1: the file's faces, sewn)
  std::string reason;
};

/// The path `options.path` asks for on `model` and why. Throws nurbs::InputError naming the flag
/// and the fix for an unknown path, --path immersed with --faces or --thickness, or several
/// solids of which one is to be immersed without choosing it (--solids). A file of faces only
/// takes the immersed path when asked (solid -1: read_cad_solid sews them into one solid).
ImportPath choose_import_path(const geometry::CadModel& model, const ImportCommandOptions& options);

/// The faces of `faces` as the case's "faces" list (what a user chooses supports and loads from).
nlohmann::ordered_json faces_json(const std::vector<geometry::SolidFace>& faces);

/// The immersed case of solid `solid` of `part` (see above); `output` is where it is written (its
/// "file" is relative to that folder). `solids` is how many solids the file holds ("solid" is
/// written only when there are several).
nlohmann::ordered_json immersed_case_skeleton(const std::filesystem::path& part,
                                              const std::filesystem::path& output, int solid,
                                              int solids,
                                              const std::vector<geometry::SolidFace>& faces);

/// The case as written: one top-level field per line, one face per line of "faces".
std::string immersed_case_text(const nlohmann::ordered_json& c);

/// The immersed path's part of import's report (after the counts, the body-fitted face notes and
/// the solids' notes): the chosen solid, its faces, OpenCascade's volume, the case written to
/// `output` and what to do next.
void immersed_import_report(const ImportCommandResult& r, const ImportCommandOptions& options,
                            const std::string& output, nlohmann::json& json,
                            io::MarkdownReport& md);

}  // namespace isospring::workflows
