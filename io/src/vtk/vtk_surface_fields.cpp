#include "isospring/io/vtk_surface_fields.hpp"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <stdexcept>

#include "vtk_internal.hpp"

namespace isospring::io {

void write_surface_fields_vtp(const std::filesystem::path& path,
                              const geometry::CadTriangulation& mesh,
                              const std::vector<SurfacePointField>& fields) {
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
  const size_t n = mesh.points.size();
  for (const SurfacePointField& field : fields) {
    if (!field.vectors.empty()) {
      data->GetPointData()->AddArray(detail::make_vector_array(field.name, field.vectors, n));
      continue;
    }
    if (field.scalars.size() != n)
      throw std::invalid_argument("write_surface_fields_vtp: field " + field.name + " has " +
                                  std::to_string(field.scalars.size()) + " values for " +
                                  std::to_string(n) + " points");
    auto array = detail::make_double_array(field.name, 1, static_cast<vtkIdType>(n));
    for (size_t i = 0; i < n; ++i) array->SetValue(static_cast<vtkIdType>(i), field.scalars[i]);
    data->GetPointData()->AddArray(array);
  }
  detail::write_xml_dataset(path, data);
}

}  // namespace isospring::io
