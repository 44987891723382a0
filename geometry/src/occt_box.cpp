// Axis-aligned boxes of OpenCascade shapes (occt_box.hpp).
#include "occt_box.hpp"

#include <BRepBndLib.hxx>

namespace isospring::geometry::detail {

Corners corners(const Bnd_Box& box) {
  double x0, y0, z0, x1, y1, z1;
  box.Get(x0, y0, z0, x1, y1, z1);
  return {Eigen::Vector3d(x0, y0, z0), Eigen::Vector3d(x1, y1, z1)};
}

Corners tight_box(const TopoDS_Shape& shape) {
  Bnd_Box box;
  BRepBndLib::AddOptimal(shape, box, false, false);
  return corners(box);
}

}  // namespace isospring::geometry::detail
