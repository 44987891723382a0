#include "isospring/geometry/cad_triangulation.hpp"

#include <BRepBndLib.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRep_Tool.hxx>
#include <Bnd_Box.hxx>
#include <Poly_Triangulation.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopLoc_Location.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <cmath>
#include <stdexcept>
#include <string>

#include "cad_reader.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::geometry {

CadTriangulation triangulate_cad(const std::filesystem::path& file, double relative_deflection) {
  if (!(relative_deflection > 0.0 && relative_deflection < 1.0))
    throw nurbs::InputError(file.string() + ": the display deflection must be in (0, 1) of the " +
                            "part size, got " + std::to_string(relative_deflection));
  std::string unit;
  const TopoDS_Shape shape = detail::read_cad_shape(file, unit);
  CadTriangulation mesh;
  try {
    Bnd_Box box;
    BRepBndLib::Add(shape, box);
    const double diagonal = std::sqrt(box.SquareExtent());
    // Angular deflection 0.2 rad keeps small holes round even when the chordal bound is loose.
    BRepMesh_IncrementalMesh mesher(shape, relative_deflection * diagonal, false, 0.2, true);
    if (!mesher.IsDone()) throw std::runtime_error(file.string() + ": OpenCascade could not mesh");
    // Faces in the order read_cad() numbers them (TopExp::MapShapes).
    TopTools_IndexedMapOfShape faces;
    TopExp::MapShapes(shape, TopAbs_FACE, faces);
    for (int f = 1; f <= faces.Extent(); ++f) {
      const TopoDS_Face& face = TopoDS::Face(faces(f));
      TopLoc_Location location;
      const Handle(Poly_Triangulation) triangulation = BRep_Tool::Triangulation(face, location);
      if (triangulation.IsNull())
        throw std::runtime_error(file.string() + ": OpenCascade left face " +
                                 std::to_string(f - 1) + " without a triangulation");
      const int offset = static_cast<int>(mesh.points.size());
      const gp_Trsf transform = location.Transformation();
      for (int n = 1; n <= triangulation->NbNodes(); ++n) {
        const gp_Pnt p = triangulation->Node(n).Transformed(transform);
        mesh.points.emplace_back(p.X(), p.Y(), p.Z());
      }
      // A reversed face's outward normal is opposite to its surface normal.
      const bool reversed = face.Orientation() == TopAbs_REVERSED;
      for (int t = 1; t <= triangulation->NbTriangles(); ++t) {
        int a = 0, b = 0, c = 0;
        triangulation->Triangle(t).Get(a, b, c);
        if (reversed) std::swap(b, c);
        mesh.triangles.push_back({offset + a - 1, offset + b - 1, offset + c - 1});
        mesh.triangle_face.push_back(f - 1);
      }
    }
  } catch (const Standard_Failure& e) {
    throw std::runtime_error(file.string() +
                             ": OpenCascade failed to mesh: " + e.GetMessageString());
  }
  return mesh;
}

}  // namespace isospring::geometry
