// Sampled VTK output of patches: the whole parametric domain (write_patches_sampled_vtu) or the
// outer sides of solid patches (write_boundary_sampled_vtu), both as structured grids of exact
// points joined by linear cells.
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>

#include <array>
#include <exception>
#include <mutex>
#include <stdexcept>

#include "isospring/io/vtk_boundary.hpp"
#include "isospring/io/vtk_patches.hpp"
#include "vtk_internal.hpp"

namespace isospring::io {
namespace {
using Dims = std::array<int, 3>;

/// One structured grid of sample parameters on a patch: u[d] along direction d (a single value
/// for a direction the grid does not extend in: the unused directions of a surface, the fixed
/// parameter of a side).
struct SampleGrid {
  int patch = 0;
  std::array<std::vector<double>, 3> u{std::vector<double>{0.0}, std::vector<double>{0.0},
                                       std::vector<double>{0.0}};
  Dims size() const {
    return {static_cast<int>(u[0].size()), static_cast<int>(u[1].size()),
            static_cast<int>(u[2].size())};
  }
};

/// Parameters of a direction: every element split into `samples` equal steps, breaks included.
std::vector<double> sample_parameters(const nurbs::KnotVector& knots, int samples) {
  const std::vector<double> breaks = knots.unique();
  std::vector<double> u;
  for (size_t e = 0; e + 1 < breaks.size(); ++e)
    for (int s = 0; s < samples; ++s)
      u.push_back(breaks[e] + (breaks[e + 1] - breaks[e]) * s / samples);
  u.push_back(breaks.back());
  return u;
}

SampleGrid patch_grid(const nurbs::Patch& patch, int index, int samples) {
  SampleGrid grid;
  grid.patch = index;
  for (int d = 0; d < patch.param_dim(); ++d)
    grid.u[static_cast<size_t>(d)] = sample_parameters(patch.knots(d), samples);
  return grid;
}

/// Linear cells of a grid of n[0] x n[1] x n[2] points (first index fastest) starting at point
/// `offset`: lines, quadrilaterals or hexahedra over the directions with more than one point.
void add_grid_cells(vtkUnstructuredGrid* cells, const Dims& n, vtkIdType offset) {
  std::vector<int> active;
  for (int d = 0; d < 3; ++d)
    if (n[static_cast<size_t>(d)] > 1) active.push_back(d);
  auto id = [&](Dims ijk) { return offset + ijk[0] + n[0] * (ijk[1] + n[1] * ijk[2]); };
  // The point `steps` away from `base` along the active directions.
  auto at = [&](const Dims& base, int a, int b, int c) {
    Dims ijk = base;
    const int step[3] = {a, b, c};
    for (size_t k = 0; k < active.size(); ++k) ijk[static_cast<size_t>(active[k])] += step[k];
    return id(ijk);
  };
  Dims last = n;
  for (int d : active) --last[static_cast<size_t>(d)];
  for (int k = 0; k < last[2]; ++k)
    for (int j = 0; j < last[1]; ++j)
      for (int i = 0; i < last[0]; ++i) {
        const Dims b{i, j, k};
        if (active.size() == 1) {
          vtkIdType line[2] = {at(b, 0, 0, 0), at(b, 1, 0, 0)};
          cells->InsertNextCell(VTK_LINE, 2, line);
        } else if (active.size() == 2) {
          vtkIdType quad[4] = {at(b, 0, 0, 0), at(b, 1, 0, 0), at(b, 1, 1, 0), at(b, 0, 1, 0)};
          cells->InsertNextCell(VTK_QUAD, 4, quad);
        } else {
          vtkIdType hex[8] = {at(b, 0, 0, 0), at(b, 1, 0, 0), at(b, 1, 1, 0), at(b, 0, 1, 0),
                              at(b, 0, 0, 1), at(b, 1, 0, 1), at(b, 1, 1, 1), at(b, 0, 1, 1)};
          cells->InsertNextCell(VTK_HEXAHEDRON, 8, hex);
        }
      }
}

struct Sample {
  int patch;
  nurbs::Param u;
};

/// The point arrays of the samples: position, "parameter", the control fields and the evaluated
/// fields, each point written by one thread (all threads when every evaluated field is
/// thread-safe). The first exception of any thread is rethrown.
void evaluate_samples(const std::vector<nurbs::Patch>& patches, const PatchFields& fields,
                      const std::vector<Sample>& samples, vtkUnstructuredGrid* grid) {
  const auto count = static_cast<vtkIdType>(samples.size());
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(count);
  auto parameter = detail::make_double_array("parameter", 3, count);
  std::vector<vtkSmartPointer<vtkDoubleArray>> control, evaluated;
  for (const ControlField& f : fields.control)
    control.push_back(detail::make_double_array(f.name, f.components, count));
  bool parallel = true;
  for (const PatchField& f : fields.evaluated) {
    evaluated.push_back(detail::make_double_array(f.name, f.components, count));
    parallel = parallel && f.thread_safe;
  }
  // Raw storage: each thread writes its own points, without VTK's bookkeeping per tuple.
  double* xyz = vtkDoubleArray::SafeDownCast(points->GetData())->GetPointer(0);
  std::exception_ptr failure;
  std::mutex failure_mutex;
#pragma omp parallel for schedule(dynamic, 256) if (parallel && count > 1024)
  for (vtkIdType s = 0; s < count; ++s) {
    try {
      const Sample& sample = samples[static_cast<size_t>(s)];
      const nurbs::Patch& patch = patches[static_cast<size_t>(sample.patch)];
      const Eigen::Vector3d x = patch.point(sample.u);
      for (int c = 0; c < 3; ++c) {
        xyz[3 * s + c] = x[c];
        parameter->GetPointer(0)[3 * s + c] = sample.u[static_cast<size_t>(c)];
      }
      for (size_t f = 0; f < fields.control.size(); ++f) {
        const Eigen::VectorXd value = evaluate_control_field(
            patch, fields.control[f].coefficients[static_cast<size_t>(sample.patch)], sample.u);
        std::copy(value.data(), value.data() + value.size(),
                  control[f]->GetPointer(0) + s * fields.control[f].components);
      }
      for (size_t f = 0; f < fields.evaluated.size(); ++f) {
        const Eigen::VectorXd value = fields.evaluated[f].evaluate(sample.patch, sample.u);
        if (value.size() != fields.evaluated[f].components)
          throw std::invalid_argument("VTK output: field '" + fields.evaluated[f].name +
                                      "' returned the wrong number of components");
        std::copy(value.data(), value.data() + value.size(),
                  evaluated[f]->GetPointer(0) + s * fields.evaluated[f].components);
      }
    } catch (...) {
      const std::lock_guard<std::mutex> lock(failure_mutex);
      if (!failure) failure = std::current_exception();
    }
  }
  if (failure) std::rethrow_exception(failure);
  grid->SetPoints(points);
  grid->GetPointData()->AddArray(parameter);
  for (auto& a : control) grid->GetPointData()->AddArray(a);
  for (auto& a : evaluated) grid->GetPointData()->AddArray(a);
}

/// Samples `grids` into one unstructured grid with cell data "patch" and `extra` integer cell
/// arrays (one value per grid, e.g. the side), and writes it.
void write_sampled_grids(const std::filesystem::path& path,
                         const std::vector<nurbs::Patch>& patches, const PatchFields& fields,
                         const std::vector<SampleGrid>& grids,
                         const std::vector<std::pair<std::string, std::vector<int>>>& extra = {}) {
  detail::check_control_fields(patches, fields.control);
  std::vector<Sample> samples;
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  grid->Allocate();
  std::vector<size_t> cell_grid;  // the grid of every cell
  for (size_t g = 0; g < grids.size(); ++g) {
    const SampleGrid& sampled = grids[g];
    const Dims n = sampled.size();
    const auto offset = static_cast<vtkIdType>(samples.size());
    for (int k = 0; k < n[2]; ++k)
      for (int j = 0; j < n[1]; ++j)
        for (int i = 0; i < n[0]; ++i)
          samples.push_back(
              {sampled.patch,
               {sampled.u[0][static_cast<size_t>(i)], sampled.u[1][static_cast<size_t>(j)],
                sampled.u[2][static_cast<size_t>(k)]}});
    add_grid_cells(grid, n, offset);
    cell_grid.resize(static_cast<size_t>(grid->GetNumberOfCells()), g);
  }
  evaluate_samples(patches, fields, samples, grid);
  auto patch_ids = detail::make_int_array("patch", grid->GetNumberOfCells());
  for (size_t c = 0; c < cell_grid.size(); ++c)
    patch_ids->SetValue(static_cast<vtkIdType>(c), grids[cell_grid[c]].patch);
  grid->GetCellData()->AddArray(patch_ids);
  for (const auto& [name, values] : extra) {
    auto array = detail::make_int_array(name, grid->GetNumberOfCells());
    for (size_t c = 0; c < cell_grid.size(); ++c)
      array->SetValue(static_cast<vtkIdType>(c), values[cell_grid[c]]);
    grid->GetCellData()->AddArray(array);
  }
  detail::write_xml_dataset(path, grid);
}
}  // namespace

void write_patches_sampled_vtu(const std::filesystem::path& path,
                               const std::vector<nurbs::Patch>& patches, const PatchFields& fields,
                               int samples_per_element) {
  if (samples_per_element < 1)
    throw std::invalid_argument("write_patches_sampled_vtu: samples_per_element must be >= 1");
  std::vector<SampleGrid> grids;
  for (size_t p = 0; p < patches.size(); ++p)
    grids.push_back(patch_grid(patches[p], static_cast<int>(p), samples_per_element));
  write_sampled_grids(path, patches, fields, grids);
}

void write_boundary_sampled_vtu(const std::filesystem::path& path,
                                const std::vector<nurbs::Patch>& patches,
                                const std::vector<PatchSide>& sides, const PatchFields& fields,
                                int samples_per_element) {
  if (samples_per_element < 1)
    throw std::invalid_argument("write_boundary_sampled_vtu: samples_per_element must be >= 1");
  std::vector<SampleGrid> grids;
  std::vector<int> side_ids;
  for (const PatchSide& side : sides) {
    const nurbs::Patch& patch = patches.at(static_cast<size_t>(side.patch));
    if (side.dir < 0 || side.dir >= patch.param_dim() || (side.end != 0 && side.end != 1))
      throw std::invalid_argument("write_boundary_sampled_vtu: no side (" +
                                  std::to_string(side.dir) + ", " + std::to_string(side.end) +
                                  ") on patch " + std::to_string(side.patch));
    SampleGrid grid = patch_grid(patch, side.patch, samples_per_element);
    const nurbs::KnotVector& knots = patch.knots(side.dir);
    grid.u[static_cast<size_t>(side.dir)] = {side.end == 0 ? knots.first() : knots.last()};
    grids.push_back(std::move(grid));
    side_ids.push_back(2 * side.dir + side.end);
  }
  write_sampled_grids(path, patches, fields, grids, {{"side", side_ids}});
}

}  // namespace isospring::io
