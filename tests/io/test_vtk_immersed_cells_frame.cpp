// The background cells' VTK file (write_immersed_cells_vtu) of a domain whose grid is turned
// (ImmersionOptions::frame): every hexahedron must be its cell turned into the world, so each of
// the cell's quadrature points lies inside it and its volume is the knot span's. The CAx-IF nut
// (tests/data/parts/caxif_nut.stp) turned by Euler angles 20, 35 and 10 degrees and immersed in
// that frame on 2 mm cells.
#include <gtest/gtest.h>
#include <vtkPoints.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>
#include <filesystem>

#include "isospring/geometry/immersed_cad.hpp"
#include "isospring/io/vtk_immersed_cells.hpp"

namespace isospring::io {
namespace {

namespace fs = std::filesystem;

TEST(VtkImmersedCells, TurnedGridsCellsHoldTheirPoints) {
  const fs::path nut = fs::path(ISOSPRING_SOURCE_DIR) / "tests/data/parts/caxif_nut.stp";
  if (!fs::exists(nut)) GTEST_SKIP() << nut << " (a third-party part) is absent";
  const double degree = M_PI / 180.0;
  const Eigen::Matrix3d q = (Eigen::AngleAxisd(20 * degree, Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(35 * degree, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(10 * degree, Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  geometry::ImmersionOptions options;
  options.cell_size = 0.002;
  options.frame = q;
  const geometry::ImmersedDomain domain =
      geometry::immerse_solid(geometry::transform_solid(geometry::read_cad_solid(nut), q), options);
  const fs::path file = fs::temp_directory_path() / "isospring-vtk-cells-frame.vtu";
  write_immersed_cells_vtu(file, domain);
  auto reader = vtkSmartPointer<vtkXMLUnstructuredGridReader>::New();
  reader->SetFileName(file.c_str());
  reader->Update();
  vtkUnstructuredGrid* grid = reader->GetOutput();
  ASSERT_EQ(grid->GetNumberOfCells(), static_cast<vtkIdType>(domain.cells.size()));
  const double h = 0.002;
  double worst = 0, volume_error = 0;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c) {
    vtkPoints* corners = grid->GetCell(c)->GetPoints();
    const auto corner = [&](int k) {
      double x[3];
      corners->GetPoint(k, x);
      return Eigen::Vector3d(x[0], x[1], x[2]);
    };
    // VTK_HEXAHEDRON: corner 1 along the cell's first axis from corner 0, 3 along its second, 4
    // along its third.
    Eigen::Matrix3d edges;
    edges << corner(1) - corner(0), corner(3) - corner(0), corner(4) - corner(0);
    const geometry::ImmersedCell& cell = domain.cells[static_cast<size_t>(c)];
    double span = 1;
    for (int d = 0; d < 3; ++d) {
      const auto& knots = domain.background.knots(d);
      span *= domain.extent[d] * (knots[cell.span[d] + 1] - knots[cell.span[d]]);
    }
    volume_error = std::max(volume_error, std::abs(edges.determinant() - span) / span);
    const Eigen::Matrix3d inverse = edges.inverse();
    for (const Eigen::Vector3d& x : cell.points) {
      const Eigen::Vector3d t = inverse * (x - corner(0));
      worst = std::max(worst, std::max(-t.minCoeff(), t.maxCoeff() - 1.0));
    }
  }
  fs::remove(file);
  // Coordinates are written in double precision: round-off only.
  EXPECT_LT(volume_error, 1e-9);
  EXPECT_LT(worst * h, 1e-12) << "a quadrature point lies " << worst << " cells outside its cell";
}

}  // namespace
}  // namespace isospring::io
