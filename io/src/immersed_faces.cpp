// Faces of immersed supports and loads, by index or selector (see immersed_faces.hpp).
#include "immersed_faces.hpp"

#include <string>

namespace isospring::io::detail {
namespace {

using case_json::Field;
using geometry::FaceSelector;

FaceSelector read_selector(const Field& field) {
  field.expect_object({"plane", "box", "cylinder", "name", "tolerance"});
  const int kinds = static_cast<int>(field.has("plane")) + static_cast<int>(field.has("box")) +
                    static_cast<int>(field.has("cylinder")) + static_cast<int>(field.has("name"));
  if (kinds != 1)
    field.fail(
        ": give exactly one of \"plane\": {\"point\", \"normal\"}, \"box\": {\"min\", \"max\"}, "
        "\"cylinder\": {\"point\", \"axis\", \"radius\"} or \"name\": \"...\" (or a face index)");
  FaceSelector s;
  if (field.has("tolerance")) s.tolerance = field.at("tolerance").non_negative();
  if (field.has("plane")) {
    const Field plane = field.at("plane");
    plane.expect_object({"point", "normal"});
    s.kind = FaceSelector::Kind::kPlane;
    s.point = plane.at("point").vector(3);
    s.direction = plane.at("normal").vector(3);
    if (!(s.direction.norm() > 0)) plane.at("normal").fail(": the normal must not be zero");
  } else if (field.has("box")) {
    const Field box = field.at("box");
    box.expect_object({"min", "max"});
    s.kind = FaceSelector::Kind::kBox;
    s.box_min = box.at("min").vector(3);
    s.box_max = box.at("max").vector(3);
    if (!(s.box_min.array() <= s.box_max.array()).all())
      box.fail(": min must not exceed max in any direction");
  } else if (field.has("cylinder")) {
    const Field cylinder = field.at("cylinder");
    cylinder.expect_object({"point", "axis", "radius"});
    s.kind = FaceSelector::Kind::kCylinder;
    s.point = cylinder.at("point").vector(3);
    s.direction = cylinder.at("axis").vector(3);
    if (!(s.direction.norm() > 0)) cylinder.at("axis").fail(": the axis must not be zero");
    s.radius = cylinder.at("radius").positive();
  } else {
    s.kind = FaceSelector::Kind::kName;
    s.name = field.at("name").string();
    if (s.name.empty()) field.at("name").fail(": the name is empty");
  }
  return s;
}

}  // namespace

std::vector<int> ImmersedFaceChooser::faces(const Field& item) {
  const Field field = item.at("face");
  if (!field.json().is_object()) {
    const int face = field.integer();
    if (face < 0 || face >= solid_.face_count())
      field.fail(": face " + std::to_string(face) + " does not exist; the file has " +
                 std::to_string(solid_.face_count()) +
                 " faces (0-based; `isospring info` lists them)");
    return {face};
  }
  const FaceSelector selector = read_selector(field);
  if (!faces_) faces_ = geometry::solid_faces(solid_);
  const std::vector<int> chosen = geometry::select_faces(*faces_, selector);
  if (chosen.empty()) {
    std::string names;
    for (const geometry::SolidFace& f : *faces_)
      if (!f.name.empty()) names += (names.empty() ? "" : ", ") + ("'" + f.name + "'");
    field.fail(": the " + geometry::describe(selector) + " matches none of the solid's faces; " +
               (selector.kind == FaceSelector::Kind::kName
                    ? (names.empty() ? std::string("the file names no faces")
                                     : "the file's face names: " + names) +
                          "; give a face index instead (`isospring info` lists them)"
                    : std::string("every point of a face must lie on it (widen \"tolerance\", "
                                  "check the coordinates are in m) or give the face index "
                                  "(`isospring info` lists the faces)")));
  }
  return chosen;
}

}  // namespace isospring::io::detail
