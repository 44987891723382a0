// The sampled outer surface of solid models (vtk_boundary.hpp), read back with VTK's XML reader.
// Independent checks: the sides of two glued boxes are the 10 faces of the union's surface; every
// written point lies on the box face its "side" names; the identity control field (control
// values = control points) reproduces the position exactly (affine invariance); the cell count
// is the closed form sum over sides of s^2 e_a e_b; parallel evaluation writes the same numbers
// as serial evaluation; the sample count rule against its closed form.
#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "isospring/io/vtk_boundary.hpp"
#include "isospring/io/vtk_patches.hpp"
#include "isospring/nurbs/refine.hpp"

namespace isospring::io {
namespace {
namespace fs = std::filesystem;

// A box [x0, x0 + size] x [0, 1] x [0, 0.5] of degree p with n[d] elements per direction.
nurbs::Patch box(double x0, double size, int p, std::array<int, 3> n) {
  const nurbs::KnotVector linear(1, {0, 0, 1, 1});
  std::vector<Eigen::Vector3d> points;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) points.emplace_back(x0 + size * i, j, 0.5 * k);
  const nurbs::Patch linear_box({linear, linear, linear}, points);
  return nurbs::k_refine(linear_box, {p, p, p}, {n[0], n[1], n[2]});
}

analysis::Problem problem_of(std::vector<nurbs::Patch> patches) {
  analysis::Problem problem;
  problem.patches = std::move(patches);
  problem.material = {1000, 0.3, 0, 1};
  return problem;
}

// The identity field: the control points themselves, so its value at any parameter is the point.
ControlField identity(const std::vector<nurbs::Patch>& patches) {
  ControlField field{"position", 3, {}};
  for (const nurbs::Patch& patch : patches) {
    Eigen::MatrixXd c(3, patch.num_points());
    for (int a = 0; a < patch.num_points(); ++a) c.col(a) = patch.control_point(a);
    field.coefficients.push_back(c);
  }
  return field;
}

vtkSmartPointer<vtkUnstructuredGrid> read_vtu(const fs::path& path) {
  auto reader = vtkSmartPointer<vtkXMLUnstructuredGridReader>::New();
  reader->SetFileName(path.c_str());
  reader->Update();
  return reader->GetOutput();
}

TEST(VtkBoundary, TwoGluedBoxesHaveTheTenFacesOfTheirUnion) {
  const auto problem = problem_of({box(0, 1, 2, {2, 2, 2}), box(1, 1, 2, {2, 2, 2})});
  const std::vector<PatchSide> sides = outer_sides(problem);
  ASSERT_EQ(sides.size(), 10u);
  for (const PatchSide& s : sides)  // the shared face x = 1: patch 0's u1, patch 1's u0
    EXPECT_FALSE(s.dir == 0 && s.end == (s.patch == 0 ? 1 : 0)) << s.patch;
}

TEST(VtkBoundary, EveryPointIsOnItsFaceAndTheIdentityFieldIsThePosition) {
  const std::vector<nurbs::Patch> patches = {box(0, 2, 2, {3, 2, 2}), box(2, 1, 2, {2, 2, 2})};
  const auto problem = problem_of(patches);
  const std::vector<PatchSide> sides = outer_sides(problem);
  const fs::path dir = fs::temp_directory_path() / "isospring_test_vtk_boundary";
  fs::create_directories(dir);
  PatchFields fields;
  fields.control.push_back(identity(patches));
  const int s = 3;
  write_boundary_sampled_vtu(dir / "b.vtu", patches, sides, fields, s);
  const auto grid = read_vtu(dir / "b.vtu");
  // Cells: s^2 per element face of every outer side.
  long long cells = 0;
  for (const PatchSide& side : sides) {
    long long n = 1;
    for (int d = 0; d < 3; ++d)
      if (d != side.dir) n *= s * patches[side.patch].knots(d).num_elements();
    cells += n;
  }
  ASSERT_EQ(grid->GetNumberOfCells(), cells);
  vtkDataArray* side_ids = grid->GetCellData()->GetArray("side");
  vtkDataArray* patch_ids = grid->GetCellData()->GetArray("patch");
  vtkDataArray* position = grid->GetPointData()->GetArray("position");
  ASSERT_TRUE(side_ids && patch_ids && position);
  const double low[3] = {0, 0, 0}, high[3] = {3, 1, 0.5};
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c) {
    const int side = static_cast<int>(side_ids->GetTuple1(c));
    const int patch = static_cast<int>(patch_ids->GetTuple1(c));
    const int dir = side / 2, end = side % 2;
    // x faces of a patch are its own ends; y and z faces are the union's.
    const double plane = dir == 0 ? (patch == 0 ? 0.0 : 3.0) : (end == 0 ? low[dir] : high[dir]);
    vtkIdType n = 0;
    const vtkIdType* ids = nullptr;
    grid->GetCellPoints(c, n, ids);
    ASSERT_EQ(n, 4);
    for (vtkIdType k = 0; k < n; ++k) {
      double x[3], u[3];
      grid->GetPoint(ids[k], x);
      position->GetTuple(ids[k], u);
      EXPECT_NEAR(x[dir], plane, 1e-14) << c;
      for (int d = 0; d < 3; ++d) EXPECT_NEAR(u[d], x[d], 1e-14) << c;
    }
  }
  // LZ4-compressed appended binary, as the writer promises.
  std::ifstream in(dir / "b.vtu");
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_NE(text.str().find("compressor=\"vtkLZ4DataCompressor\""), std::string::npos);
  fs::remove_all(dir);
}

TEST(VtkBoundary, ParallelEvaluationWritesWhatSerialEvaluationWrites) {
  const std::vector<nurbs::Patch> patches = {box(0, 1, 2, {8, 8, 8})};
  const auto sides = outer_sides(problem_of(patches));
  auto probe = [patches](int p, const nurbs::Param& u) {
    Eigen::VectorXd out(2);
    const Eigen::Vector3d x = patches[static_cast<size_t>(p)].point(u);
    out << x.squaredNorm(), u[0] * u[1] - u[2];
    return out;
  };
  const fs::path dir = fs::temp_directory_path() / "isospring_test_vtk_boundary_parallel";
  fs::create_directories(dir);
  PatchFields serial, parallel;
  serial.evaluated.push_back(PatchField{"probe", 2, probe, false});
  parallel.evaluated.push_back(PatchField{"probe", 2, probe, true});
  write_boundary_sampled_vtu(dir / "serial.vtu", patches, sides, serial, 4);
  write_boundary_sampled_vtu(dir / "parallel.vtu", patches, sides, parallel, 4);
  const auto a = read_vtu(dir / "serial.vtu"), b = read_vtu(dir / "parallel.vtu");
  ASSERT_GT(a->GetNumberOfPoints(), 1024);  // above the writer's threshold for threads
  ASSERT_EQ(a->GetNumberOfPoints(), b->GetNumberOfPoints());
  vtkDataArray* pa = a->GetPointData()->GetArray("probe");
  vtkDataArray* pb = b->GetPointData()->GetArray("probe");
  for (vtkIdType i = 0; i < a->GetNumberOfPoints(); ++i)
    for (int c = 0; c < 2; ++c) ASSERT_EQ(pa->GetComponent(i, c), pb->GetComponent(i, c)) << i;
  fs::remove_all(dir);
}

TEST(VtkBoundary, SamplesKeepTheSurfaceInProportionToTheModel) {
  // 32^3 elements of degree 2: 34^3 control points, budget 2 x 39,304 = 78,608 points; the six
  // faces hold 6 (32 s + 1)^2 points: 99,846 at s = 4 (over), 56,454 at s = 3.
  const std::vector<nurbs::Patch> large = {box(0, 1, 2, {32, 32, 32})};
  EXPECT_EQ(boundary_samples(large, outer_sides(problem_of(large))), 3);
  // A small model is drawn at the most samples (the 50,000-point floor).
  const std::vector<nurbs::Patch> small = {box(0, 1, 2, {4, 4, 4})};
  EXPECT_EQ(boundary_samples(small, outer_sides(problem_of(small))), 4);
  // With no floor and half a point per control point: 19,652 points, s = 1 gives 6534.
  EXPECT_EQ(boundary_samples(large, outer_sides(problem_of(large)), 4, 0.5, 0), 1);
}

TEST(VtkBoundary, RejectsASideThePatchDoesNotHave) {
  const std::vector<nurbs::Patch> patches = {box(0, 1, 2, {1, 1, 1})};
  EXPECT_THROW(write_boundary_sampled_vtu(fs::temp_directory_path() / "never.vtu", patches,
                                          {{0, 3, 0}}, {}, 2),
               std::invalid_argument);
}

}  // namespace
}  // namespace isospring::io
