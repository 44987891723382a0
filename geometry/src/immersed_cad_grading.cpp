// Where an immersed grid's cells are placed on a CAD solid (immersed_cad.hpp): grading planes
// through a face's bounding box (grading_towards_face) and the coordinates of the planar faces
// normal to an axis (planar_face_coordinates).
#include <BRepAdaptor_Surface.hxx>
#include <BRepBndLib.hxx>
#include <Bnd_Box.hxx>
#include <gp_Pln.hxx>

#include <algorithm>
#include <cmath>
#include <string>

#include "cad_solid_shape.hpp"
#include "isospring/geometry/immersed_cad.hpp"
#include "isospring/nurbs/error.hpp"
#include "occt_box.hpp"

namespace isospring::geometry {

std::vector<GradingPlane> grading_towards_face(const CadSolid& solid, int face, double smallest,
                                               double ratio) {
  const CadSolid::Shape& shape = solid.shape();
  for (size_t k = 0; k < shape.faces.size(); ++k) {
    if (shape.face_index[k] != face) continue;
    // The tight box (on the exact surfaces and their trimming, without tolerance enlargement),
    // so that its planes are the face's own extreme coordinates.
    const auto [lo, hi] = detail::tight_box(shape.faces[k]);
    const double flat = 1e-9 * (hi - lo).norm();
    std::vector<GradingPlane> planes;
    for (int axis = 0; axis < 3; ++axis) {
      planes.push_back({axis, lo[axis], smallest, ratio});
      if (hi[axis] - lo[axis] > flat) planes.push_back({axis, hi[axis], smallest, ratio});
    }
    return planes;
  }
  throw nurbs::InputError(solid.name() + ": grading towards face " + std::to_string(face) +
                          ": the solid has no such face (`isospring info` lists its faces, 0.." +
                          std::to_string(solid.face_count() - 1) + ")");
}

std::array<std::vector<double>, 3> planar_face_coordinates(const CadSolid& solid) {
  const CadSolid::Shape& shape = solid.shape();
  Bnd_Box box;
  BRepBndLib::AddOptimal(shape.solid, box, false, false);
  const double merge = 1e-9 * std::sqrt(box.SquareExtent());
  std::array<std::vector<double>, 3> at;
  for (const TopoDS_Face& face : shape.faces) {
    const BRepAdaptor_Surface surface(face, false);
    if (surface.GetType() != GeomAbs_Plane) continue;
    const gp_Pln plane = surface.Plane();
    const gp_Dir n = plane.Axis().Direction();
    const double normal[3] = {n.X(), n.Y(), n.Z()};
    const double origin[3] = {plane.Location().X(), plane.Location().Y(), plane.Location().Z()};
    // Normal to axis k when the normal's other components (the sine of the angle) are below
    // 1e-9: the plane then tilts by less than 1e-9 of a grid's extent across it.
    for (int k = 0; k < 3; ++k)
      if (std::hypot(normal[(k + 1) % 3], normal[(k + 2) % 3]) < 1e-9)
        at[static_cast<size_t>(k)].push_back(origin[k]);
  }
  for (std::vector<double>& coordinates : at) {
    std::sort(coordinates.begin(), coordinates.end());
    std::vector<double> once;
    for (double x : coordinates)
      if (once.empty() || x > once.back() + merge) once.push_back(x);
    coordinates = once;
  }
  return at;
}

}  // namespace isospring::geometry
