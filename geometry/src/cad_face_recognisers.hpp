#pragma once
// The CAD face recognisers: one signature and one ordered list (cad_face_recognisers.cpp) that
// read_cad walks for every face, as for solids (cad_solid_recognisers.hpp). Adding a kind of
// face: a file cad_NAME_face.cpp defining `FaceRecognition recognise_NAME_face(const TopoDS_Face&,
// CadFace&)` and its two lines in the list.
#include <TopoDS_Face.hxx>
#include <vector>

#include "isospring/geometry/cad.hpp"

namespace isospring::geometry::detail {

struct FaceRecognition {
  bool recognised = false;
  std::vector<nurbs::Patch> patches;  // when recognised: the face's patches
  /// The face was cut into several patches (CadModel::split_patches); otherwise its one patch is
  /// a face patch (CadModel::face_patches).
  bool cut = false;
};

/// A recogniser fills its part of the report (natural, coons, split and their figures) and, when
/// it does not recognise the face, report.note with why and what to do; a later recogniser may
/// read the earlier ones' verdicts from the report. OpenCascade's exceptions propagate (read_cad
/// makes them the face's note and tries no further recogniser).
struct FaceRecogniser {
  const char* name;  // for messages and tests
  FaceRecognition (*recognise)(const TopoDS_Face&, CadFace&);
};

/// The report before any recogniser ran: the face's index, surface type, wires, edges, and
/// OpenCascade's area and perimeter.
CadFace describe_face(const TopoDS_Face& face, int index);

/// Every recogniser in the order read_cad tries them; the first that recognises a face wins.
const std::vector<FaceRecogniser>& face_recognisers();

}  // namespace isospring::geometry::detail
