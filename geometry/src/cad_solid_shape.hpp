#pragma once
// What a CadSolid holds: OpenCascade's solid and its faces with their numbers in the file.
#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>
#include <TopoDS_Solid.hxx>

#include <string>
#include <vector>

#include "isospring/geometry/immersed_cad.hpp"

namespace isospring::geometry {

struct CadSolid::Shape {
  TopoDS_Solid solid;
  std::vector<TopoDS_Face> faces;  // the solid's faces (TopExp::MapShapes order)
  std::vector<int> face_index;     // each one's index among the file's faces (`isospring info`)
  int file_faces = 0;              // faces of the whole file
};

namespace detail {

/// A CadSolid of a shape built in memory (a solid, or a compound holding exactly one), checked as
/// read_cad_solid checks a file's: closed, valid, positive volume. Faces are numbered in the
/// shape's own order. Throws nurbs::InputError naming `name` otherwise.
CadSolid make_cad_solid(const TopoDS_Shape& shape, const std::string& name);

}  // namespace detail
}  // namespace isospring::geometry
