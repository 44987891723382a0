#include "isospring/io/vtk_immersed_cells.hpp"

#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>

#include <algorithm>
#include <stdexcept>

#include "vtk_internal.hpp"

namespace isospring::io {
namespace {

// The knot interval [lo, hi] of direction d holding the cell: found from the mean of its
// quadrature points (which lie in the cell), not from a stored index.
std::array<double, 2> interval(const geometry::ImmersedDomain& domain,
                               const geometry::ImmersedCell& cell, int d) {
  double mean = 0;  // in grid coordinates (along the frame's axes)
  for (const Eigen::Vector3d& x : cell.points) mean += domain.to_grid(x)[d];
  mean /= static_cast<double>(cell.points.size());
  const nurbs::KnotVector& knots = domain.background.knots(d);
  const double u = std::clamp((mean - domain.origin[d]) / domain.extent[d], 0.0, 1.0);
  const int span = knots.find_span(u);
  const std::vector<double>& k = knots.values();
  return {domain.origin[d] + domain.extent[d] * k[static_cast<size_t>(span)],
          domain.origin[d] + domain.extent[d] * k[static_cast<size_t>(span) + 1]};
}

}  // namespace

void write_immersed_cells_vtu(const std::filesystem::path& path,
                              const geometry::ImmersedDomain& domain) {
  if (domain.dimension != 3)
    throw std::invalid_argument("write_immersed_cells_vtu: a 3D immersed domain is needed");
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  const auto n = static_cast<vtkIdType>(domain.cells.size());
  auto kind = detail::make_int_array("kind", n);
  auto fraction = detail::make_double_array("fraction", 1, n);
  grid->Allocate(n);
  for (vtkIdType c = 0; c < n; ++c) {
    const geometry::ImmersedCell& cell = domain.cells[static_cast<size_t>(c)];
    if (cell.points.empty()) continue;
    const auto x = interval(domain, cell, 0), y = interval(domain, cell, 1),
               z = interval(domain, cell, 2);
    vtkIdType ids[8];
    // VTK_HEXAHEDRON: the bottom face counter-clockwise seen from above, then the top face.
    const double corners[8][3] = {{x[0], y[0], z[0]}, {x[1], y[0], z[0]}, {x[1], y[1], z[0]},
                                  {x[0], y[1], z[0]}, {x[0], y[0], z[1]}, {x[1], y[0], z[1]},
                                  {x[1], y[1], z[1]}, {x[0], y[1], z[1]}};
    // The corners are grid coordinates; the file holds world ones (the hexahedron turned by the
    // frame, which keeps its orientation and volume).
    for (int k = 0; k < 8; ++k) {
      const Eigen::Vector3d world =
          domain.to_world(Eigen::Vector3d(corners[k][0], corners[k][1], corners[k][2]));
      ids[k] = points->InsertNextPoint(world.x(), world.y(), world.z());
    }
    grid->InsertNextCell(VTK_HEXAHEDRON, 8, ids);
    double volume = 0;
    for (double w : cell.weights) volume += w;
    const vtkIdType id = grid->GetNumberOfCells() - 1;
    kind->SetValue(id, cell.kind == geometry::CellKind::kCut ? 1 : 0);
    fraction->SetValue(id, volume / ((x[1] - x[0]) * (y[1] - y[0]) * (z[1] - z[0])));
  }
  kind->SetNumberOfTuples(grid->GetNumberOfCells());
  fraction->SetNumberOfTuples(grid->GetNumberOfCells());
  grid->SetPoints(points);
  grid->GetCellData()->AddArray(kind);
  grid->GetCellData()->AddArray(fraction);
  detail::write_xml_dataset(path, grid);
}

}  // namespace isospring::io
