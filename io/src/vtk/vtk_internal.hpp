#pragma once
// Private helpers shared by the VTK writers (io/src/vtk/vtk_*.cpp): array construction and atomic
// XML output through VTK's own writers.
#include <vtkDataObject.h>
#include <vtkDoubleArray.h>
#include <vtkIntArray.h>
#include <vtkSmartPointer.h>

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "isospring/io/vtk_fields.hpp"
#include "isospring/nurbs/patch.hpp"

namespace isospring::io::detail {

vtkSmartPointer<vtkDoubleArray> make_double_array(const std::string& name, int components,
                                                  vtkIdType tuples);
vtkSmartPointer<vtkIntArray> make_int_array(const std::string& name, vtkIdType tuples);

/// A 3-component array from vectors; `values` must have `expected` entries, otherwise
/// std::invalid_argument names the array (a caller bug, not user input).
vtkSmartPointer<vtkDoubleArray> make_vector_array(const std::string& name,
                                                  const std::vector<Eigen::Vector3d>& values,
                                                  size_t expected);

/// Throws std::invalid_argument when a control field does not have one components x
/// num_points matrix per patch (a caller bug).
void check_control_fields(const std::vector<nurbs::Patch>& patches,
                          const std::vector<ControlField>& fields);

/// Writes a vtkUnstructuredGrid (.vtu) or vtkPolyData (.vtp) with VTK's XML writers (appended,
/// LZ4-compressed binary) atomically. Throws nurbs::InputError naming the path on failure.
void write_xml_dataset(const std::filesystem::path& path, vtkDataObject* data);

}  // namespace isospring::io::detail
