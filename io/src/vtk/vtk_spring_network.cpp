#include "isospring/io/vtk_spring_network.hpp"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

#include <stdexcept>

#include "vtk_internal.hpp"

namespace isospring::io {

void write_spring_network_vtp(const std::filesystem::path& path,
                              const analysis::SpringNetwork& network,
                              const std::vector<PointVectors>& vectors,
                              const std::vector<Eigen::Vector3d>& deformation) {
  const size_t count = network.positions.size();
  if (network.masses.size() != count || network.fixed.size() != count)
    throw std::invalid_argument("write_spring_network_vtp: inconsistent particle arrays");
  if (!deformation.empty() && deformation.size() != count)
    throw std::invalid_argument("write_spring_network_vtp: deformation size mismatch");

  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(count));
  auto mass = detail::make_double_array("mass", 1, static_cast<vtkIdType>(count));
  auto fixed = detail::make_int_array("fixed", static_cast<vtkIdType>(count));
  for (size_t p = 0; p < count; ++p) {
    const auto id = static_cast<vtkIdType>(p);
    const Eigen::Vector3d x = deformation.empty()
                                  ? network.positions[p]
                                  : Eigen::Vector3d(network.positions[p] + deformation[p]);
    points->SetPoint(id, x.data());
    mass->SetValue(id, network.masses[p]);
    fixed->SetValue(id, network.fixed[p] ? 1 : 0);
  }

  const auto springs = static_cast<vtkIdType>(network.springs.size());
  auto lines = vtkSmartPointer<vtkCellArray>::New();
  auto stiffness = detail::make_double_array("stiffness", 1, springs);
  auto damping = detail::make_double_array("damping", 1, springs);
  auto rest_length = detail::make_double_array("rest_length", 1, springs);
  auto group = detail::make_int_array("group", springs);
  for (vtkIdType s = 0; s < springs; ++s) {
    const analysis::Spring& spring = network.springs[static_cast<size_t>(s)];
    const vtkIdType ends[2] = {spring.i, spring.j};
    lines->InsertNextCell(2, ends);
    stiffness->SetValue(s, spring.stiffness);
    damping->SetValue(s, spring.damping);
    rest_length->SetValue(s, spring.rest_length);
    group->SetValue(s, spring.group);
  }

  auto data = vtkSmartPointer<vtkPolyData>::New();
  data->SetPoints(points);
  data->SetLines(lines);
  data->GetPointData()->AddArray(mass);
  data->GetPointData()->AddArray(fixed);
  for (const PointVectors& v : vectors)
    data->GetPointData()->AddArray(detail::make_vector_array(v.name, v.values, count));
  data->GetCellData()->AddArray(stiffness);
  data->GetCellData()->AddArray(damping);
  data->GetCellData()->AddArray(rest_length);
  data->GetCellData()->AddArray(group);
  detail::write_xml_dataset(path, data);
}

}  // namespace isospring::io
