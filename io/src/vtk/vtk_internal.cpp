#include "vtk_internal.hpp"

#include <vtkDataSet.h>
#include <vtkPolyData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataWriter.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <cstdint>
#include <limits>
#include <stdexcept>

#include "isospring/io/atomic_file.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::io::detail {

vtkSmartPointer<vtkDoubleArray> make_double_array(const std::string& name, int components,
                                                  vtkIdType tuples) {
  auto array = vtkSmartPointer<vtkDoubleArray>::New();
  array->SetName(name.c_str());
  array->SetNumberOfComponents(components);
  array->SetNumberOfTuples(tuples);
  return array;
}

vtkSmartPointer<vtkIntArray> make_int_array(const std::string& name, vtkIdType tuples) {
  auto array = vtkSmartPointer<vtkIntArray>::New();
  array->SetName(name.c_str());
  array->SetNumberOfComponents(1);
  array->SetNumberOfTuples(tuples);
  return array;
}

vtkSmartPointer<vtkDoubleArray> make_vector_array(const std::string& name,
                                                  const std::vector<Eigen::Vector3d>& values,
                                                  size_t expected) {
  if (values.size() != expected)
    throw std::invalid_argument("VTK output: array '" + name + "' has " +
                                std::to_string(values.size()) + " values for " +
                                std::to_string(expected) + " points");
  auto array = make_double_array(name, 3, static_cast<vtkIdType>(values.size()));
  for (size_t i = 0; i < values.size(); ++i)
    array->SetTuple(static_cast<vtkIdType>(i), values[i].data());
  return array;
}

void check_control_fields(const std::vector<nurbs::Patch>& patches,
                          const std::vector<ControlField>& fields) {
  for (const ControlField& field : fields) {
    bool ok = field.coefficients.size() == patches.size();
    for (size_t p = 0; ok && p < patches.size(); ++p)
      ok = field.coefficients[p].rows() == field.components &&
           field.coefficients[p].cols() == patches[p].num_points();
    if (!ok)
      throw std::invalid_argument("VTK output: control field '" + field.name +
                                  "' does not match the patches' control nets");
  }
}

namespace {
template <typename Writer>
void write_with(const std::filesystem::path& path, vtkDataObject* data) {
  write_via_temporary(path, [&](const std::filesystem::path& temporary) {
    auto writer = vtkSmartPointer<Writer>::New();
    writer->SetFileName(temporary.c_str());
    writer->SetInputData(data);
    writer->SetDataModeToAppended();
    // 32-bit point ids and block headers where they suffice: half the connectivity's bytes.
    auto* set = vtkDataSet::SafeDownCast(data);
    if (set != nullptr && set->GetNumberOfPoints() < std::numeric_limits<int32_t>::max()) {
      writer->SetIdTypeToInt32();
      writer->SetHeaderTypeToUInt32();
    }
    writer->EncodeAppendedDataOff();
    // LZ4: about as small as zlib on these arrays of doubles (which compress little either
    // way) and several times faster to write and to read.
    writer->SetCompressorTypeToLZ4();
    if (writer->Write() != 1)
      throw nurbs::InputError("cannot write '" + path.string() +
                              "': VTK's writer failed (disk full or folder not writable?)");
  });
}
}  // namespace

void write_xml_dataset(const std::filesystem::path& path, vtkDataObject* data) {
  if (vtkUnstructuredGrid::SafeDownCast(data) != nullptr)
    write_with<vtkXMLUnstructuredGridWriter>(path, data);
  else if (vtkPolyData::SafeDownCast(data) != nullptr)
    write_with<vtkXMLPolyDataWriter>(path, data);
  else
    throw std::invalid_argument("write_xml_dataset: only unstructured grids and poly data");
}

}  // namespace isospring::io::detail
