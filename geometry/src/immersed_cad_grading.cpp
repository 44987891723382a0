// Grading planes through a face's bounding box (immersed_cad.hpp, grading_towards_face).
#include <BRepBndLib.hxx>
#include <Bnd_Box.hxx>

#include <string>

#include "cad_solid_shape.hpp"
#include "isospring/geometry/immersed_cad.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::geometry {

std::vector<GradingPlane> grading_towards_face(const CadSolid& solid, int face, double smallest,
                                               double ratio) {
  const CadSolid::Shape& shape = solid.shape();
  for (size_t k = 0; k < shape.faces.size(); ++k) {
    if (shape.face_index[k] != face) continue;
    // The tight box (on the exact surfaces and their trimming, without tolerance enlargement),
    // so that its planes are the face's own extreme coordinates.
    Bnd_Box box;
    BRepBndLib::AddOptimal(shape.faces[k], box, false, false);
    double lo[3], hi[3];
    box.Get(lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
    const double flat =
        1e-9 * (Eigen::Vector3d(hi[0], hi[1], hi[2]) - Eigen::Vector3d(lo[0], lo[1], lo[2])).norm();
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

}  // namespace isospring::geometry
