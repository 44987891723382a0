#pragma once
// The CAD solid recognisers: one signature and one ordered list (cad_solid_recognisers.cpp) that
// read_cad walks for every solid. Adding a kind of solid: a file cad_NAME.cpp defining
// `SolidRecognition recognise_NAME(const SolidContext&)` and its two lines in the list.
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>
#include <functional>
#include <string>
#include <vector>

#include "isospring/geometry/cad.hpp"
#include "isospring/nurbs/patch.hpp"

namespace isospring::geometry::detail {

/// The patches a face became (natural, Coons or cut), empty when it did not become patches.
using FacePatches = std::function<std::vector<nurbs::Patch>(const TopoDS_Face&)>;

/// What a recogniser may use besides the solid: read_cad has already converted every face, so a
/// recogniser builds on the face patches instead of converting faces again.
struct SolidContext {
  const TopoDS_Shape& solid;
  double volume;  // OpenCascade's, to check the patches against
  /// The natural patch of a face of the solid (nullptr when the face is trimmed or failed).
  std::function<const nurbs::Patch*(const TopoDS_Shape&)> natural_patch;
  FacePatches face_patches;
};

struct SolidRecognition {
  bool recognised = false;
  std::vector<nurbs::Patch> patches;  // when recognised: the solid's volume patches, in order
  /// When not recognised: why, for the solid's note (joined with the other recognisers' by
  /// "; "); empty adds nothing (the solid is plainly not of this kind and others say more).
  std::string why;
  std::string remark;  // when recognised: what a user should know (empty: nothing)
  /// The solid is of this kind but could not be built: its note is this `why` alone, and later
  /// recognisers are not tried (their "not a ..." would only hide the real reason).
  bool final = false;
};

struct SolidRecogniser {
  const char* name;  // for messages and tests
  SolidRecognition (*recognise)(const SolidContext&);
};

/// The patches face f (0-based, in the model's face order) became: its natural or Coons patch,
/// or the patches of its cut; empty when it became none.
std::vector<nurbs::Patch> model_face_patches(const CadModel& model, int f);

/// The context read_cad gives the recognisers for `solid`: lookups into the patches the faces of
/// `model` became (`faces`: the shape's face map, in the model's face order). It refers to
/// `solid`, `model` and `faces`, which must outlive it.
SolidContext solid_context(const TopoDS_Shape& solid, double volume, const CadModel& model,
                           const TopTools_IndexedMapOfShape& faces);

/// Every recogniser in the order read_cad tries them; the first that recognises a solid wins.
const std::vector<SolidRecogniser>& solid_recognisers();

}  // namespace isospring::geometry::detail
