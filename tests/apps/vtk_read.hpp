#pragma once
// Reading the commands' VTK outputs back with VTK's own XML readers (end-to-end tests).
#include <vtkDataArray.h>
#include <vtkInformation.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLMultiBlockDataReader.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <Eigen/Core>
#include <filesystem>
#include <map>
#include <string>

namespace isospring::testing {

inline vtkSmartPointer<vtkUnstructuredGrid> read_vtu(const std::filesystem::path& path) {
  auto reader = vtkSmartPointer<vtkXMLUnstructuredGridReader>::New();
  reader->SetFileName(path.c_str());
  reader->Update();
  return reader->GetOutput();
}

inline vtkSmartPointer<vtkPolyData> read_vtp(const std::filesystem::path& path) {
  auto reader = vtkSmartPointer<vtkXMLPolyDataReader>::New();
  reader->SetFileName(path.c_str());
  reader->Update();
  return reader->GetOutput();
}

/// The blocks of a .vtm by name (read through vtkXMLMultiBlockDataReader, so the .vtm and every
/// piece it references must be valid).
inline std::map<std::string, vtkSmartPointer<vtkDataObject>> read_vtm(
    const std::filesystem::path& path) {
  auto reader = vtkSmartPointer<vtkXMLMultiBlockDataReader>::New();
  reader->SetFileName(path.c_str());
  reader->Update();
  std::map<std::string, vtkSmartPointer<vtkDataObject>> blocks;
  vtkMultiBlockDataSet* mb = vtkMultiBlockDataSet::SafeDownCast(reader->GetOutput());
  if (!mb) return blocks;
  for (unsigned b = 0; b < mb->GetNumberOfBlocks(); ++b) {
    const char* name = mb->GetMetaData(b)->Get(vtkCompositeDataSet::NAME());
    blocks[name ? name : ""] = mb->GetBlock(b);
  }
  return blocks;
}

inline Eigen::VectorXd tuple(vtkDataArray* array, vtkIdType i) {
  Eigen::VectorXd v(array->GetNumberOfComponents());
  array->GetTuple(i, v.data());
  return v;
}

inline Eigen::Vector3d point(vtkDataSet* data, vtkIdType i) {
  double x[3];
  data->GetPoint(i, x);
  return {x[0], x[1], x[2]};
}

}  // namespace isospring::testing
