#include "isospring/io/vtk_triangulation.hpp"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

#include "vtk_internal.hpp"

namespace isospring::io {

void write_triangulation_vtp(const std::filesystem::path& path,
                             const geometry::CadTriangulation& mesh) {
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  for (const Eigen::Vector3d& p : mesh.points) points->InsertNextPoint(p.data());
  auto polys = vtkSmartPointer<vtkCellArray>::New();
  auto face = detail::make_int_array("face", static_cast<vtkIdType>(mesh.triangles.size()));
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const vtkIdType ids[3] = {mesh.triangles[t][0], mesh.triangles[t][1], mesh.triangles[t][2]};
    polys->InsertNextCell(3, ids);
    face->SetValue(static_cast<vtkIdType>(t), mesh.triangle_face[t]);
  }
  auto data = vtkSmartPointer<vtkPolyData>::New();
  data->SetPoints(points);
  data->SetPolys(polys);
  data->GetCellData()->AddArray(face);
  detail::write_xml_dataset(path, data);
}

}  // namespace isospring::io
