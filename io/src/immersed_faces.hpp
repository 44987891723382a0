#pragma once
// The faces a support or load of an immersed case acts on: its "face" field is a face index (as
// `isospring info` lists them) or a selector object (geometry/cad_face_selection.hpp):
//   {"plane": {"point": [x, y, z], "normal": [nx, ny, nz]}}
//   {"box": {"min": [x0, y0, z0], "max": [x1, y1, z1]}}
//   {"cylinder": {"point": [x, y, z], "axis": [ax, ay, az], "radius": r}}
//   {"name": "clamp"}                       (the face's name in the STEP file)
// each with an optional "tolerance" in m (default 1e-6). A selector may match several faces; one
// that matches none is an error naming the field and the fix.
#include <optional>
#include <vector>

#include "case_file_json.hpp"
#include "isospring/geometry/cad_face_selection.hpp"

namespace isospring::io::detail {

class ImmersedFaceChooser {
 public:
  explicit ImmersedFaceChooser(const geometry::CadSolid& solid) : solid_(solid) {}
  /// The faces named by item's "face" field (one for an index, one or more for a selector).
  std::vector<int> faces(const case_json::Field& item);

 private:
  const geometry::CadSolid& solid_;
  std::optional<std::vector<geometry::SolidFace>> faces_;  // described when a selector needs them
};

}  // namespace isospring::io::detail
