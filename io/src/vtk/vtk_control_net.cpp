#include "isospring/io/vtk_control_net.hpp"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

#include <stdexcept>

#include "vtk_internal.hpp"

namespace isospring::io {

void write_control_net_vtp(const std::filesystem::path& path,
                           const std::vector<nurbs::Patch>& patches,
                           const std::vector<ControlField>& fields) {
  vtkIdType count = 0;
  for (const nurbs::Patch& patch : patches) count += patch.num_points();
  for (const ControlField& f : fields) {
    bool ok = f.coefficients.size() == patches.size();
    for (size_t p = 0; ok && p < patches.size(); ++p)
      ok = f.coefficients[p].rows() == f.components &&
           f.coefficients[p].cols() == patches[p].num_points();
    if (!ok)
      throw std::invalid_argument("write_control_net_vtp: field '" + f.name +
                                  "' does not match the control nets");
  }

  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(count);
  auto weight = detail::make_double_array("weight", 1, count);
  auto point_patch = detail::make_int_array("patch", count);
  std::vector<vtkSmartPointer<vtkDoubleArray>> arrays;
  for (const ControlField& f : fields)
    arrays.push_back(detail::make_double_array(f.name, f.components, count));
  auto lines = vtkSmartPointer<vtkCellArray>::New();
  auto line_patch = detail::make_int_array("patch", 0);
  auto line_direction = detail::make_int_array("direction", 0);

  vtkIdType offset = 0;
  for (size_t p = 0; p < patches.size(); ++p) {
    const nurbs::Patch& patch = patches[p];
    for (int a = 0; a < patch.num_points(); ++a) {
      points->SetPoint(offset + a, patch.control_point(a).data());
      weight->SetValue(offset + a, patch.weight(a));
      point_patch->SetValue(offset + a, static_cast<int>(p));
      for (size_t f = 0; f < fields.size(); ++f)
        arrays[f]->SetTuple(offset + a, fields[f].coefficients[p].col(a).eval().data());
    }
    // One polyline per row of the net in each direction.
    for (int d = 0; d < patch.param_dim(); ++d) {
      const int others[2] = {(d + 1) % 3, (d + 2) % 3};
      for (int b = 0; b < patch.num_points(others[1]); ++b)
        for (int a = 0; a < patch.num_points(others[0]); ++a) {
          lines->InsertNextCell(patch.num_points(d));
          for (int t = 0; t < patch.num_points(d); ++t) {
            std::array<int, 3> ijk{};
            ijk[static_cast<size_t>(d)] = t;
            ijk[static_cast<size_t>(others[0])] = a;
            ijk[static_cast<size_t>(others[1])] = b;
            lines->InsertCellPoint(offset + patch.index(ijk[0], ijk[1], ijk[2]));
          }
          line_patch->InsertNextValue(static_cast<int>(p));
          line_direction->InsertNextValue(d);
        }
    }
    offset += patch.num_points();
  }

  auto data = vtkSmartPointer<vtkPolyData>::New();
  data->SetPoints(points);
  data->SetLines(lines);
  data->GetPointData()->AddArray(weight);
  data->GetPointData()->AddArray(point_patch);
  for (auto& a : arrays) data->GetPointData()->AddArray(a);
  data->GetCellData()->AddArray(line_patch);
  data->GetCellData()->AddArray(line_direction);
  detail::write_xml_dataset(path, data);
}

}  // namespace isospring::io
