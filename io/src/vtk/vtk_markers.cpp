#include "isospring/io/vtk_markers.hpp"

#include <vtkCellArray.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

#include "vtk_internal.hpp"

namespace isospring::io {

void write_markers_vtp(const std::filesystem::path& path, const MarkerData& markers) {
  const size_t count = markers.positions.size();
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  auto vertices = vtkSmartPointer<vtkCellArray>::New();
  for (size_t m = 0; m < count; ++m) {
    const vtkIdType id = points->InsertNextPoint(markers.positions[m].data());
    vertices->InsertNextCell(1, &id);
  }
  auto data = vtkSmartPointer<vtkPolyData>::New();
  data->SetPoints(points);
  data->SetVerts(vertices);
  for (const MarkerCase& c : markers.cases) {
    data->GetPointData()->AddArray(
        detail::make_vector_array("measured_" + c.load_case, c.measured, count));
    data->GetPointData()->AddArray(
        detail::make_vector_array("model_" + c.load_case, c.model, count));
    std::vector<Eigen::Vector3d> residual(count);
    auto magnitude = detail::make_double_array("residual_magnitude_" + c.load_case, 1,
                                               static_cast<vtkIdType>(count));
    for (size_t m = 0; m < count; ++m) {
      residual[m] = c.measured[m] - c.model[m];
      magnitude->SetValue(static_cast<vtkIdType>(m), residual[m].norm());
    }
    data->GetPointData()->AddArray(
        detail::make_vector_array("residual_" + c.load_case, residual, count));
    data->GetPointData()->AddArray(magnitude);
  }
  detail::write_xml_dataset(path, data);
}

}  // namespace isospring::io
