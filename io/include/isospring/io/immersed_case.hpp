#pragma once
// Case files whose geometry is an immersed CAD solid ("geometry": {"type": "immersed", ...}):
// the part's exact B-rep embedded in a B-spline background grid (geometry/immersed_cad.hpp),
// supports and loads on the part's faces by index (as `isospring info` lists them) or by a
// selector (a plane, a box, a cylinder or the face's STEP name; geometry/cad_face_selection.hpp),
// which may match several faces. The schema is in docs/case-files.md ("Immersed geometry");
// `isospring analyze` runs such a case, and `isospring import` writes one for a part it cannot
// turn into body-fitted volumes (workflows/import_immersed.hpp).
//
//   {"name": "cylinder", "geometry": {"type": "immersed", "file": "part.step", "solid": 1,
//                                      "cells": [6, 6, 6], "degree": 2},
//    "material": {"E": 2.1e11, "nu": 0.3, "density": 7850},
//    "analysis": {"volumetric": "bbar", "ghost_fraction": 0.02, "ghost_penalty": 0.01},
//                                          (optional; "displacement" and these values by default)
//    "boundary": [{"face": 0, "fix": ["x", "y", "z"]},
//                 {"face": {"plane": {"point": [0, 0, 0.01], "normal": [0, 0, 1]}},
//                  "symmetry": true}],
//    "load_cases": [{"id": "gravity", "gravity": [0, 0, -9.81]}]}
//
// Every problem is a nurbs::InputError naming the case file, the field and the fix, found before
// any computation (the solid is read and validated, face indices checked against it).
#include <Eigen/Core>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "isospring/analysis/immersed.hpp"
#include "isospring/geometry/immersed_cad.hpp"
#include "isospring/io/case_file.hpp"

namespace isospring::io {

/// One load case: tractions and pressures on faces, body force and gravity over the part.
struct ImmersedLoadCase {
  std::string id;
  std::vector<analysis::ImmersedTraction> tractions;
  std::vector<analysis::ImmersedPressure> pressures;
  Eigen::Vector3d body_force = Eigen::Vector3d::Zero();  // N/m^3
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();     // m/s^2
};

struct ImmersedCase {
  std::string name;
  std::filesystem::path file;  // the case file (as given)
  nlohmann::json raw;          // the document as read
  std::filesystem::path part;  // the CAD file, resolved against the case file's folder
  int solid = -1;              // as read_cad_solid takes it
  std::shared_ptr<const geometry::CadSolid> cad;  // read and validated
  geometry::ImmersionOptions immersion;
  /// Which axes the grid follows ("geometry": {"frame": ...}), for reports: "file" (the file's
  /// axes, the default), "principal" (the part's principal axes of inertia) or "user".
  std::string frame = "file";
  std::string frame_note;  // principal_frame's fallback, when it took one
  analysis::Material material;
  /// "analysis": {"volumetric": "bbar"}: mean-dilatation B-bar (analysis::ImmersedOptions), for
  /// nearly incompressible parts; "displacement" (the default) otherwise.
  analysis::Volumetric volumetric = analysis::Volumetric::kDisplacement;
  /// "analysis": {"ghost_fraction": f, "ghost_penalty": g}: the ghost penalty on the faces of cut
  /// cells with less of the part than f, of strength g (analysis::ImmersedOptions' defaults
  /// without them). A solve whose stiffness is not positive definite widens f and warns.
  double ghost_fraction = analysis::ImmersedOptions{}.ghost_fraction;
  double ghost_penalty = analysis::ImmersedOptions{}.ghost_penalty;
  std::vector<analysis::ImmersedSupport> supports;
  std::vector<ImmersedLoadCase> load_cases;
  bool write_cells = false;  // "output": {"cells": true}: also the background cells (cells.vtu)
  /// `"analytic"`: a 3D closed form the part reproduces (as in body-fitted cases, e.g.
  /// hollow_sphere); `study` measures its errors against it.
  std::optional<AnalyticSolution> analytic;
};

/// True when the document's "geometry" is {"type": "immersed", ...}.
bool is_immersed_case(const nlohmann::json& document);

/// Reads and validates an immersed case file (and reads its CAD solid).
ImmersedCase read_immersed_case(const std::filesystem::path& path);

/// The same from a parsed document; `case_file` names it in messages and anchors relative paths.
ImmersedCase build_immersed_case(const nlohmann::json& document,
                                 const std::filesystem::path& case_file);

/// "bbar" or "displacement", as the case file spells the formulation of the volumetric strain.
std::string volumetric_key(analysis::Volumetric volumetric);

/// The same in words for the reports ("B-bar: ..." or "displacement formulation").
std::string volumetric_sentence(analysis::Volumetric volumetric);

/// The solver options of one load case (supports, material and that case's loads).
analysis::ImmersedOptions immersed_options(const ImmersedCase& c, const ImmersedLoadCase& load);

}  // namespace isospring::io
