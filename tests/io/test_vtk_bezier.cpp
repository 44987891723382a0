// Bezier-cell output against NURBS evaluation. The written file is read back with VTK's reader
// and evaluated twice, independently of the writer: (a) by VTK itself (vtkBezierCurve /
// Quadrilateral / Hexahedron::EvaluateLocation with the file's rational weights), which also
// checks the point ordering VTK expects; (b) by our own rational Bernstein evaluation of the
// read-back points and weights. Both must match nurbs::Patch::point to 1e-12 on random rational
// patches with repeated knots, and an affine control field must be reproduced exactly.
#include <gtest/gtest.h>
#include <unistd.h>  // getpid: CTest runs tests in parallel processes
#include <vtkCell.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <random>

#include "isospring/io/vtk_patches.hpp"
#include "isospring/nurbs/refine.hpp"
#include "random_patch.hpp"

namespace isospring::io {
namespace {
namespace fs = std::filesystem;
using Eigen::Vector3d;

double binomial(int n, int k) {
  double b = 1;
  for (int i = 1; i <= k; ++i) b = b * (n - k + i) / i;
  return b;
}

double bernstein(int p, int i, double t) {
  return binomial(p, i) * std::pow(t, i) * std::pow(1 - t, p - i);
}

/// VTK's higher-order point numbering (vtkHigherOrderQuadrilateral/Hexahedron documentation):
/// corners counter-clockwise (bottom then top for hexes), then edge interiors (bottom ring,
/// top ring, vertical edges), then faces (-i, +i, -j, +j, -k, +k) and the interior, each
/// block with its first index fastest. Curves: the two ends, then the interior.
int vtk_index(int dim, int i, int j, int k, const std::array<int, 3>& p) {
  const auto edge = [](int a, int pa) { return a > 0 && a < pa; };
  if (dim == 1) return i == 0 ? 0 : (i == p[0] ? 1 : 1 + i);
  const int corner_i = i == 0 ? 0 : 1, corner_j = j == 0 ? 0 : 1;
  const int ring[2][2] = {{0, 3}, {1, 2}};  // [i end][j end] -> corner number
  const int ni = p[0] - 1, nj = p[1] - 1, nk = dim == 3 ? p[2] - 1 : 0;
  const bool ii = edge(i, p[0]), jj = edge(j, p[1]), kk = dim == 3 && edge(k, p[2]);
  const int corners = dim == 2 ? 4 : 8;
  const int layer = dim == 3 && k == p[2] ? 1 : 0;
  if (!ii && !jj && !kk) return ring[corner_i][corner_j] + 4 * layer;
  int offset = corners;
  const int ring_edges = 2 * ni + 2 * nj;  // interior points on one ring of four edges
  if (!kk && (ii != jj)) {                 // an edge of the bottom or top ring
    offset += layer * ring_edges;
    if (ii) return offset + (j == 0 ? 0 : ni + nj) + (i - 1);
    return offset + (i == 0 ? 2 * ni + nj : ni) + (j - 1);
  }
  if (dim == 2) return offset + ring_edges + (i - 1) + ni * (j - 1);
  offset += 2 * ring_edges;
  if (kk && !ii && !jj) return offset + nk * ring[corner_i][corner_j] + (k - 1);
  offset += 4 * nk;
  if (!ii) return offset + (i == 0 ? 0 : nj * nk) + (j - 1) + nj * (k - 1);
  offset += 2 * nj * nk;
  if (!jj) return offset + (j == 0 ? 0 : ni * nk) + (i - 1) + ni * (k - 1);
  offset += 2 * ni * nk;
  if (!kk) return offset + (k == 0 ? 0 : ni * nj) + (i - 1) + ni * (j - 1);
  offset += 2 * ni * nj;
  return offset + (i - 1) + ni * ((j - 1) + nj * (k - 1));
}

struct Evaluated {
  Vector3d x, field;
};

/// Rational Bezier evaluation of one cell from read-back points, weights and a point field.
Evaluated own_evaluation(vtkUnstructuredGrid* grid, vtkIdType cell, int dim,
                         const std::array<int, 3>& p, const std::array<double, 3>& t,
                         vtkDataArray* field) {
  vtkIdType count = 0;
  const vtkIdType* ids = nullptr;
  grid->GetCellPoints(cell, count, ids);
  vtkDataArray* weights = grid->GetPointData()->GetRationalWeights();
  Eigen::Vector4d h = Eigen::Vector4d::Zero();
  Vector3d hf = Vector3d::Zero();
  for (int k = 0; k <= (dim == 3 ? p[2] : 0); ++k)
    for (int j = 0; j <= (dim >= 2 ? p[1] : 0); ++j)
      for (int i = 0; i <= p[0]; ++i) {
        const vtkIdType id = ids[vtk_index(dim, i, j, k, p)];
        double b = bernstein(p[0], i, t[0]);
        if (dim >= 2) b *= bernstein(p[1], j, t[1]);
        if (dim == 3) b *= bernstein(p[2], k, t[2]);
        const double w = weights->GetTuple1(id);
        Vector3d x, f;
        grid->GetPoint(id, x.data());
        field->GetTuple(id, f.data());
        h.head<3>() += b * w * x;
        h(3) += b * w;
        hf += b * w * f;
      }
  return {h.head<3>() / h(3), hf / h(3)};
}

class VtkBezier : public ::testing::TestWithParam<int> {};

TEST_P(VtkBezier, CellsReproduceThePatchExactly) {
  const int dim = GetParam();
  std::mt19937 rng(100 + static_cast<unsigned>(dim));
  std::vector<nurbs::Patch> patches;
  for (int n = 0; n < 3; ++n) patches.push_back(testing::random_patch(rng, dim, 3, true));
  // Degree >= 2 in every direction, so edge, face and interior Bezier points all occur.
  patches.push_back(nurbs::elevate_degree(testing::random_patch(rng, dim, 2, true), 1));
  Eigen::Matrix3d A = Eigen::Matrix3d::Random();
  const Vector3d b(0.3, -0.2, 0.7);
  std::vector<std::vector<Vector3d>> values;
  for (const nurbs::Patch& patch : patches) {
    values.emplace_back();
    for (const Vector3d& x : patch.control_points()) values.back().push_back(A * x + b);
  }
  const fs::path dir = fs::temp_directory_path() /
                       (std::string("isospring_test_vtk_bezier-") + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path path = dir / ("bezier" + std::to_string(dim) + ".vtu");
  write_patches_bezier_vtu(path, patches, {control_vector_field("u", values)});

  auto reader = vtkSmartPointer<vtkXMLUnstructuredGridReader>::New();
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkUnstructuredGrid* grid = reader->GetOutput();
  ASSERT_NE(grid->GetPointData()->GetRationalWeights(), nullptr);
  vtkDataArray* degrees = grid->GetCellData()->GetHigherOrderDegrees();
  ASSERT_NE(degrees, nullptr);
  vtkDataArray* field = grid->GetPointData()->GetArray("u");
  ASSERT_NE(field, nullptr);

  // Shared Bezier points: a patch with E_d elements of degree p_d has prod(E_d p_d + 1) points.
  vtkIdType expected_points = 0, expected_cells = 0;
  for (const nurbs::Patch& patch : patches) {
    vtkIdType points = 1, cells = 1;
    for (int d = 0; d < dim; ++d) {
      points *= patch.knots(d).num_elements() * patch.degree(d) + 1;
      cells *= patch.knots(d).num_elements();
    }
    expected_points += points;
    expected_cells += cells;
  }
  ASSERT_EQ(grid->GetNumberOfPoints(), expected_points);
  ASSERT_EQ(grid->GetNumberOfCells(), expected_cells);

  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double worst_vtk = 0, worst_own = 0, worst_field_vtk = 0, worst_field_own = 0;
  vtkIdType cell = 0;
  for (const nurbs::Patch& patch : patches) {
    std::array<std::vector<double>, 3> breaks{std::vector<double>{0, 1}, std::vector<double>{0, 1},
                                              std::vector<double>{0, 1}};
    std::array<int, 3> p{0, 0, 0}, elements{1, 1, 1};
    for (int d = 0; d < dim; ++d) {
      breaks[static_cast<size_t>(d)] = patch.knots(d).unique();
      p[static_cast<size_t>(d)] = patch.degree(d);
      elements[static_cast<size_t>(d)] = patch.knots(d).num_elements();
    }
    for (int ek = 0; ek < elements[2]; ++ek)
      for (int ej = 0; ej < elements[1]; ++ej)
        for (int ei = 0; ei < elements[0]; ++ei, ++cell) {
          EXPECT_EQ(grid->GetCellType(cell),
                    dim == 1 ? VTK_BEZIER_CURVE
                             : (dim == 2 ? VTK_BEZIER_QUADRILATERAL : VTK_BEZIER_HEXAHEDRON));
          for (int d = 0; d < dim; ++d)
            EXPECT_EQ(degrees->GetComponent(cell, d), p[static_cast<size_t>(d)]);
          vtkCell* vtk_cell = grid->GetCell(cell);
          std::vector<double> shape(static_cast<size_t>(vtk_cell->GetNumberOfPoints()));
          for (int sample = 0; sample < 6; ++sample) {
            // Corners first (exactness at element boundaries), then random interior points.
            std::array<double, 3> t{unit(rng), unit(rng), unit(rng)};
            if (sample < 2) t = {double(sample), double(sample), double(sample)};
            const int e[3] = {ei, ej, ek};
            nurbs::Param u{0, 0, 0};
            for (int d = 0; d < dim; ++d) {
              const auto& br = breaks[static_cast<size_t>(d)];
              u[static_cast<size_t>(d)] =
                  br[static_cast<size_t>(e[d])] +
                  t[static_cast<size_t>(d)] *
                      (br[static_cast<size_t>(e[d]) + 1] - br[static_cast<size_t>(e[d])]);
            }
            const Vector3d expected = patch.point(u);
            const Vector3d expected_field = A * expected + b;

            int sub = 0;
            double pc[3] = {t[0], dim >= 2 ? t[1] : 0.0, dim == 3 ? t[2] : 0.0};
            Vector3d x_vtk;
            vtk_cell->EvaluateLocation(sub, pc, x_vtk.data(), shape.data());
            Vector3d field_vtk = Vector3d::Zero();
            for (size_t a = 0; a < shape.size(); ++a) {
              Vector3d f;
              field->GetTuple(vtk_cell->GetPointId(static_cast<vtkIdType>(a)), f.data());
              field_vtk += shape[a] * f;
            }
            const Evaluated own = own_evaluation(grid, cell, dim, p, t, field);
            worst_vtk = std::max(worst_vtk, (x_vtk - expected).norm());
            worst_own = std::max(worst_own, (own.x - expected).norm());
            worst_field_vtk = std::max(worst_field_vtk, (field_vtk - expected_field).norm());
            worst_field_own = std::max(worst_field_own, (own.field - expected_field).norm());
          }
        }
  }
  // Coordinates and weights are O(1); extraction and evaluation cost a few dozen roundings.
  EXPECT_LT(worst_vtk, 1e-12);
  EXPECT_LT(worst_own, 1e-12);
  EXPECT_LT(worst_field_vtk, 1e-12);
  EXPECT_LT(worst_field_own, 1e-12);
  std::printf("dim %d: max |x_vtk - X| = %.2e, |x_own - X| = %.2e, field %.2e / %.2e\n", dim,
              worst_vtk, worst_own, worst_field_vtk, worst_field_own);
}

INSTANTIATE_TEST_SUITE_P(AllDimensions, VtkBezier, ::testing::Values(1, 2, 3));

}  // namespace
}  // namespace isospring::io
