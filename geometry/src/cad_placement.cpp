// Rigid placements of a CAD solid and its principal axes of inertia (immersed_cad.hpp).
#include "cad_placement.hpp"

#include <BRepBuilderAPI_Transform.hxx>
#include <BRepGProp.hxx>
#include <GProp_GProps.hxx>
#include <GProp_PrincipalProps.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <gp_Trsf.hxx>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <sstream>

#include "cad_solid_shape.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::geometry {

using nurbs::InputError;

void detail::check_rotation(const Eigen::Matrix3d& rotation, const std::string& what) {
  const double off =
      (rotation.transpose() * rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  // Round-off of a rotation built from angles in double precision is a few 1e-16.
  if (!std::isfinite(off) || off > 1e-12) {
    std::ostringstream message;
    message << what << " is not a rotation: its columns are not orthonormal (|R^T R - I| = " << off
            << " > 1e-12); give three unit axes at right angles";
    throw InputError(message.str());
  }
  if (rotation.determinant() < 0.0)
    throw InputError(what +
                     " is a reflection (determinant -1), not a rotation: give right-handed "
                     "axes (the third the cross product of the first two)");
}

bool detail::is_identity(const Eigen::Matrix3d& rotation) {
  return rotation == Eigen::Matrix3d::Identity();
}

CadSolid transform_solid(const CadSolid& solid, const Eigen::Matrix3d& rotation,
                         const Eigen::Vector3d& translation) {
  detail::check_rotation(rotation, solid.name() + ": transform_solid's rotation");
  if (!translation.allFinite())
    throw InputError(solid.name() + ": transform_solid's translation must be finite");
  const Eigen::Matrix3d& r = rotation;
  const Eigen::Vector3d& t = translation;
  gp_Trsf trsf;
  try {
    trsf.SetValues(r(0, 0), r(0, 1), r(0, 2), t.x(), r(1, 0), r(1, 1), r(1, 2), t.y(), r(2, 0),
                   r(2, 1), r(2, 2), t.z());
    // Copy: the geometry itself is transformed (not a location on the old one), so every later
    // query sees plain surfaces, as for a solid read from a file.
    BRepBuilderAPI_Transform transform(solid.shape().solid, trsf, Standard_True);
    auto shape = std::make_shared<CadSolid::Shape>();
    shape->solid = TopoDS::Solid(transform.Shape());
    shape->file_faces = solid.shape().file_faces;
    shape->face_index = solid.shape().face_index;
    // Each face's image, in the original's order, so that face k of the result is face k of
    // the original (and carries its file index). The image is taken as it occurs in the new
    // solid: ModifiedShape keys on the face's geometry and drops its orientation in the shell,
    // which carries the outward normal of a reversed face (a bore).
    TopTools_IndexedMapOfShape faces;
    TopExp::MapShapes(shape->solid, TopAbs_FACE, faces);
    for (const TopoDS_Face& face : solid.shape().faces) {
      const int index = faces.FindIndex(transform.ModifiedShape(face));
      if (index < 1)
        throw InputError(solid.name() + ": OpenCascade's placed solid lost a face; check the part");
      shape->faces.push_back(TopoDS::Face(faces(index)));
    }
    return CadSolid(std::move(shape), solid.name());
  } catch (const Standard_Failure& e) {
    throw InputError(solid.name() + ": OpenCascade could not place the solid (" +
                     e.GetMessageString() + ")");
  }
}

namespace {

Eigen::Vector3d vector_of(const gp_Vec& v) {
  return {v.X(), v.Y(), v.Z()};
}

// Flipped so that its largest component in absolute value (the lowest index on a tie) is
// positive.
Eigen::Vector3d signed_axis(Eigen::Vector3d axis) {
  int k = 0;
  for (int d = 1; d < 3; ++d)
    if (std::abs(axis[d]) > std::abs(axis[k]) + 1e-12) k = d;
  return axis[k] < 0.0 ? Eigen::Vector3d(-axis) : axis;
}

// The world axis least aligned with `odd`, projected into the plane normal to it.
Eigen::Vector3d in_plane_axis(const Eigen::Vector3d& odd) {
  int k = 0;
  for (int d = 1; d < 3; ++d)
    if (std::abs(odd[d]) < std::abs(odd[k]) - 1e-12) k = d;
  const Eigen::Vector3d e = Eigen::Vector3d::Unit(k);
  return (e - e.dot(odd) * odd).normalized();
}

}  // namespace

PrincipalFrame principal_frame(const CadSolid& solid) {
  GProp_GProps props;
  BRepGProp::VolumeProperties(solid.shape().solid, props, 1e-10);
  const GProp_PrincipalProps principal = props.PrincipalProperties();
  std::array<double, 3> moments{};
  principal.Moments(moments[0], moments[1], moments[2]);
  const std::array<Eigen::Vector3d, 3> axes = {vector_of(principal.FirstAxisOfInertia()),
                                               vector_of(principal.SecondAxisOfInertia()),
                                               vector_of(principal.ThirdAxisOfInertia())};
  std::array<int, 3> order{0, 1, 2};
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return moments[static_cast<size_t>(a)] < moments[static_cast<size_t>(b)];
  });
  PrincipalFrame frame;
  const gp_Pnt c = props.CentreOfMass();
  frame.centroid = {c.X(), c.Y(), c.Z()};
  for (int k = 0; k < 3; ++k) frame.moments[k] = moments[static_cast<size_t>(order[k])];
  const double equal = 1e-6 * frame.moments.cwiseAbs().maxCoeff();
  const bool low_pair = frame.moments[1] - frame.moments[0] <= equal;
  const bool high_pair = frame.moments[2] - frame.moments[1] <= equal;
  Eigen::Vector3d first, second;
  if (low_pair && high_pair) {
    frame.axes = Eigen::Matrix3d::Identity();
    frame.note = "all three principal moments are equal to 1e-6: the world's axes are used";
    return frame;
  }
  if (low_pair || high_pair) {
    // The odd axis (the third when the low two are equal, the first when the high two are).
    const Eigen::Vector3d odd =
        signed_axis(axes[static_cast<size_t>(order[low_pair ? 2 : 0])].normalized());
    const Eigen::Vector3d in_plane = in_plane_axis(odd);
    if (low_pair) {
      first = in_plane;
      second = odd.cross(first);
    } else {
      first = odd;
      second = in_plane;
    }
    frame.note = std::string("principal moments ") + (low_pair ? "1 and 2" : "2 and 3") +
                 " are equal to 1e-6: their axes are not defined by the part, the world axis "
                 "least aligned with the other one is used in their plane";
  } else {
    first = signed_axis(axes[static_cast<size_t>(order[0])].normalized());
    second = axes[static_cast<size_t>(order[1])].normalized();
    second = signed_axis((second - second.dot(first) * first).normalized());
  }
  frame.axes.col(0) = first;
  frame.axes.col(1) = second;
  frame.axes.col(2) = first.cross(second);
  return frame;
}

}  // namespace isospring::geometry
