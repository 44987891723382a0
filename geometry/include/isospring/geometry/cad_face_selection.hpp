#pragma once
// The faces of a CAD solid described and chosen by where they lie, for supports and loads of
// immersed cases: besides the face index (as `isospring info` lists them), a face is selected
// by a plane, a box, a cylinder or its name in the STEP file (ADVANCED_FACE name).
//
// A selector matches a face when every sample point of the face meets it: the points of its edges
// (17 per edge, ends included) and of an 8 x 8 grid over its parameter rectangle that lie on the
// face (OpenCascade's 2D face classifier). Sampling checks a face's own points, so it needs no
// surface-type rules: a cylinder selector matches a cylindrical face, but also a B-spline face that
// lies on the cylinder. A name matches a face whose STEP entity carries exactly that name.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "isospring/geometry/immersed_cad.hpp"

namespace isospring::geometry {

/// One face of a solid: what `import` lists so that a user can choose supports and loads.
struct SolidFace {
  int index = -1;            // among the file's faces (as `isospring info` numbers them)
  std::string surface_type;  // plane, cylinder, cone, sphere, torus, bspline, ...
  std::string name;          // the STEP entity's name ("" when none, or not a STEP file)
  double area = 0.0;         // OpenCascade's (BRepGProp), m^2
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  Eigen::Vector3d box_min = Eigen::Vector3d::Zero(), box_max = Eigen::Vector3d::Zero();
  /// Planes: the outward unit normal (the face's orientation in the solid); zero otherwise.
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  /// Cylinders: a point on the axis, its unit direction and the radius; zero otherwise.
  Eigen::Vector3d axis_point = Eigen::Vector3d::Zero(), axis = Eigen::Vector3d::Zero();
  double radius = 0.0;
  std::vector<Eigen::Vector3d> samples;  // the points the selectors test (see above)
};

/// Every face of the solid, in the solid's order. Names are read from the file when it is STEP.
std::vector<SolidFace> solid_faces(const CadSolid& solid);

struct FaceSelector {
  enum class Kind { kPlane, kBox, kCylinder, kName };
  Kind kind = Kind::kPlane;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();      // plane: on it; cylinder: on the axis
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();  // plane: normal; cylinder: axis
  Eigen::Vector3d box_min = Eigen::Vector3d::Zero(), box_max = Eigen::Vector3d::Zero();
  double radius = 0.0;      // cylinder
  std::string name;         // kName
  double tolerance = 1e-6;  // m: distance to the plane or the cylinder, growth of the box
};

/// File indices of the faces the selector matches (ascending; empty when none). Throws
/// nurbs::InputError for a zero normal or axis, a negative radius or tolerance, or a box whose
/// min exceeds its max.
std::vector<int> select_faces(const std::vector<SolidFace>& faces, const FaceSelector& selector);

/// One line per selector kind's meaning, e.g. "plane through (0, 0, 0) normal (1, 0, 0)", for
/// messages.
std::string describe(const FaceSelector& selector);

}  // namespace isospring::geometry
