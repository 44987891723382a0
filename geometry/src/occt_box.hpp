#pragma once
// Axis-aligned boxes of OpenCascade shapes as two Eigen corners: the import's part and face boxes
// and the immersion's solid, face and edge boxes all read them this way.
#include <Bnd_Box.hxx>
#include <TopoDS_Shape.hxx>

#include <Eigen/Core>

namespace isospring::geometry::detail {

struct Corners {
  Eigen::Vector3d lo, hi;
};

/// The corners of an OpenCascade box (with its gap, as Bnd_Box::Get gives them).
Corners corners(const Bnd_Box& box);

/// The tight box of `shape`: BRepBndLib::AddOptimal on the exact surfaces and their trimming,
/// without the tolerance enlargement, so that its planes are the shape's own extreme coordinates.
Corners tight_box(const TopoDS_Shape& shape);

}  // namespace isospring::geometry::detail
