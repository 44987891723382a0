// VTK outputs read back with VTK's own XML readers. Independent checks: sampled points are the
// patch's points at the written parameters; an affine control field a + A x reproduces
// a + A X(xi) exactly at every sample (partition of unity and affine invariance of NURBS).
#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDataArray.h>
#include <vtkIdList.h>
#include <vtkInformation.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLMultiBlockDataReader.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <fstream>
#include <random>
#include <regex>
#include <sstream>

#include "isospring/io/vtk_control_net.hpp"
#include "isospring/io/vtk_multiblock.hpp"
#include "isospring/io/vtk_patches.hpp"
#include "isospring/io/vtk_time_series.hpp"
#include "random_patch.hpp"

namespace isospring::io {
namespace {
namespace fs = std::filesystem;
using Eigen::Vector3d;

fs::path temp_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("isospring_test_vtk_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

vtkSmartPointer<vtkUnstructuredGrid> read_vtu(const fs::path& path) {
  auto reader = vtkSmartPointer<vtkXMLUnstructuredGridReader>::New();
  reader->SetFileName(path.c_str());
  reader->Update();
  return reader->GetOutput();
}

vtkSmartPointer<vtkPolyData> read_vtp(const fs::path& path) {
  auto reader = vtkSmartPointer<vtkXMLPolyDataReader>::New();
  reader->SetFileName(path.c_str());
  reader->Update();
  return reader->GetOutput();
}

Vector3d tuple3(vtkDataArray* a, vtkIdType i) {
  double v[3];
  a->GetTuple(i, v);
  return {v[0], v[1], v[2]};
}

struct Affine {
  Eigen::Matrix3d A;
  Vector3d b;
  Vector3d operator()(const Vector3d& x) const { return A * x + b; }
};

Affine random_affine(std::mt19937& rng) {
  std::uniform_real_distribution<double> d(-1, 1);
  Affine f;
  for (int r = 0; r < 3; ++r) {
    f.b(r) = d(rng);
    for (int c = 0; c < 3; ++c) f.A(r, c) = d(rng);
  }
  return f;
}

ControlField affine_field(const std::string& name, const std::vector<nurbs::Patch>& patches,
                          const Affine& f) {
  std::vector<std::vector<Vector3d>> values;
  for (const nurbs::Patch& p : patches) {
    values.emplace_back();
    for (const Vector3d& x : p.control_points()) values.back().push_back(f(x));
  }
  return control_vector_field(name, values);
}

analysis::SpringNetwork triangle_network() {
  analysis::SpringNetwork n;
  n.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  n.masses = {1.0, 2.0, 3.0};
  n.fixed = {true, false, false};
  n.springs = {
      {0, 1, 10.0, 0.1, 1.0, 0}, {1, 2, 20.0, 0.2, std::sqrt(2.0), 1}, {0, 2, 30.0, 0.3, 1.0, -1}};
  return n;
}

TEST(VtkOutput, SampledPatchesAreExactPointsWithExactAffineFields) {
  std::mt19937 rng(7);
  const std::vector<nurbs::Patch> patches = {testing::random_patch(rng, 1, 3, true),
                                             testing::random_patch(rng, 2, 3, true),
                                             testing::random_patch(rng, 3, 2, true)};
  const Affine f = random_affine(rng);
  PatchFields fields;
  fields.control.push_back(affine_field("displacement_L1", patches, f));
  // An evaluated field that depends on the patch and the parameter in a known way.
  fields.evaluated.push_back(PatchField{"probe", 2, [](int p, const nurbs::Param& u) {
                                          Eigen::VectorXd v(2);
                                          v << p, u[0] + 10 * u[1] + 100 * u[2];
                                          return v;
                                        }});
  const int samples = 3;
  const fs::path path = temp_dir("sampled") / "geometry.vtu";
  write_patches_sampled_vtu(path, patches, fields, samples);
  const auto grid = read_vtu(path);

  vtkIdType expected_points = 0, expected_cells = 0;
  for (const nurbs::Patch& p : patches) {
    vtkIdType points = 1, cells = 1;
    for (int d = 0; d < p.param_dim(); ++d) {
      points *= p.knots(d).num_elements() * samples + 1;
      cells *= p.knots(d).num_elements() * samples;
    }
    expected_points += points;
    expected_cells += cells;
  }
  ASSERT_EQ(grid->GetNumberOfPoints(), expected_points);
  ASSERT_EQ(grid->GetNumberOfCells(), expected_cells);

  vtkDataArray* parameter = grid->GetPointData()->GetArray("parameter");
  vtkDataArray* displacement = grid->GetPointData()->GetArray("displacement_L1");
  vtkDataArray* probe = grid->GetPointData()->GetArray("probe");
  vtkDataArray* patch_id = grid->GetCellData()->GetArray("patch");
  ASSERT_TRUE(parameter && displacement && probe && patch_id);
  ASSERT_EQ(probe->GetNumberOfComponents(), 2);

  // Every point: find its patch through a cell, then compare against the patch itself.
  std::vector<int> point_patch(static_cast<size_t>(grid->GetNumberOfPoints()), -1);
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c) {
    const int p = static_cast<int>(patch_id->GetTuple1(c));
    const int dim = patches[static_cast<size_t>(p)].param_dim();
    EXPECT_EQ(grid->GetCellType(c), dim == 1 ? VTK_LINE : (dim == 2 ? VTK_QUAD : VTK_HEXAHEDRON));
    auto ids = vtkSmartPointer<vtkIdList>::New();
    grid->GetCellPoints(c, ids);
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
      point_patch[static_cast<size_t>(ids->GetId(k))] = p;
  }
  double worst_point = 0, worst_field = 0;
  for (vtkIdType i = 0; i < grid->GetNumberOfPoints(); ++i) {
    const int p = point_patch[static_cast<size_t>(i)];
    ASSERT_GE(p, 0);
    const Vector3d u = tuple3(parameter, i);
    const Vector3d x = patches[static_cast<size_t>(p)].point({u[0], u[1], u[2]});
    Vector3d written;
    grid->GetPoint(i, written.data());
    worst_point = std::max(worst_point, (written - x).norm());
    worst_field = std::max(worst_field, (tuple3(displacement, i) - f(x)).norm());
    EXPECT_EQ(probe->GetComponent(i, 0), p);
    EXPECT_DOUBLE_EQ(probe->GetComponent(i, 1), u[0] + 10 * u[1] + 100 * u[2]);
  }
  EXPECT_EQ(worst_point, 0.0);    // doubles in binary: written as computed
  EXPECT_LT(worst_field, 1e-13);  // affine invariance, rounding only (|x|, |A| ~ 1)
}

TEST(VtkOutput, SampledGridContainsElementBoundaries) {
  // Two elements per direction on [0, 2] x [0, 1]: with 2 samples the parameters are the
  // breaks and the midpoints.
  const nurbs::Patch square(
      {nurbs::KnotVector::uniform(1, 2, 0.0, 2.0), nurbs::KnotVector::uniform(1, 1)},
      {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 1, 0}});
  const fs::path path = temp_dir("breaks") / "g.vtu";
  write_patches_sampled_vtu(path, {square}, {}, 2);
  const auto grid = read_vtu(path);
  vtkDataArray* parameter = grid->GetPointData()->GetArray("parameter");
  ASSERT_EQ(grid->GetNumberOfPoints(), 5 * 3);
  std::vector<double> expected_u = {0, 0.5, 1, 1.5, 2};
  for (int i = 0; i < 5; ++i)
    EXPECT_DOUBLE_EQ(parameter->GetComponent(i, 0), expected_u[static_cast<size_t>(i)]);
  EXPECT_DOUBLE_EQ(parameter->GetComponent(5, 1), 0.5);
}

TEST(VtkOutput, MismatchedFieldIsACallerError) {
  std::mt19937 rng(3);
  const std::vector<nurbs::Patch> patches = {testing::random_patch(rng, 2, 2, false)};
  PatchFields fields;
  fields.control.push_back(ControlField{"bad", 3, {Eigen::MatrixXd::Zero(3, 1)}});
  EXPECT_THROW(write_patches_sampled_vtu(temp_dir("bad") / "g.vtu", patches, fields),
               std::invalid_argument);
}

TEST(VtkOutput, SpringNetworkReadsBack) {
  const analysis::SpringNetwork n = triangle_network();
  const std::vector<Vector3d> u = {{0, 0, 0}, {0.1, 0, 0}, {0, -0.2, 0.3}};
  const fs::path path = temp_dir("springs") / "springs.vtp";
  write_spring_network_vtp(path, n, {{"displacement_L1", u}});
  const auto data = read_vtp(path);
  ASSERT_EQ(data->GetNumberOfPoints(), 3);
  ASSERT_EQ(data->GetNumberOfLines(), 3);
  for (vtkIdType p = 0; p < 3; ++p) {
    Vector3d x;
    data->GetPoint(p, x.data());
    EXPECT_EQ(x, n.positions[static_cast<size_t>(p)]);
    EXPECT_EQ(data->GetPointData()->GetArray("mass")->GetTuple1(p),
              n.masses[static_cast<size_t>(p)]);
    EXPECT_EQ(data->GetPointData()->GetArray("fixed")->GetTuple1(p), p == 0 ? 1 : 0);
    EXPECT_EQ(tuple3(data->GetPointData()->GetArray("displacement_L1"), p),
              u[static_cast<size_t>(p)]);
  }
  for (vtkIdType s = 0; s < 3; ++s) {
    const analysis::Spring& spring = n.springs[static_cast<size_t>(s)];
    auto ids = vtkSmartPointer<vtkIdList>::New();
    data->GetCellPoints(s, ids);
    ASSERT_EQ(ids->GetNumberOfIds(), 2);
    EXPECT_EQ(ids->GetId(0), spring.i);
    EXPECT_EQ(ids->GetId(1), spring.j);
    EXPECT_EQ(data->GetCellData()->GetArray("stiffness")->GetTuple1(s), spring.stiffness);
    EXPECT_EQ(data->GetCellData()->GetArray("damping")->GetTuple1(s), spring.damping);
    EXPECT_EQ(data->GetCellData()->GetArray("rest_length")->GetTuple1(s), spring.rest_length);
    EXPECT_EQ(data->GetCellData()->GetArray("group")->GetTuple1(s), spring.group);
  }
  EXPECT_THROW(write_spring_network_vtp(path, n, {{"short", {Vector3d::Zero()}}}),
               std::invalid_argument);
}

TEST(VtkOutput, ControlNetHasEveryNetLine) {
  std::mt19937 rng(11);
  const std::vector<nurbs::Patch> patches = {testing::random_patch(rng, 2, 3, true),
                                             testing::random_patch(rng, 3, 2, true)};
  const Affine f = random_affine(rng);
  const fs::path path = temp_dir("net") / "net.vtp";
  write_control_net_vtp(path, patches, {affine_field("u", patches, f)});
  const auto data = read_vtp(path);
  vtkIdType points = 0, lines = 0;
  for (const nurbs::Patch& p : patches) {
    points += p.num_points();
    for (int d = 0; d < p.param_dim(); ++d) lines += p.num_points() / p.num_points(d);
  }
  ASSERT_EQ(data->GetNumberOfPoints(), points);
  EXPECT_EQ(data->GetNumberOfLines(), lines);
  vtkIdType offset = 0;
  for (const nurbs::Patch& p : patches) {
    for (int a = 0; a < p.num_points(); ++a) {
      Vector3d x;
      data->GetPoint(offset + a, x.data());
      EXPECT_EQ(x, p.control_point(a));
      EXPECT_EQ(data->GetPointData()->GetArray("weight")->GetTuple1(offset + a), p.weight(a));
      EXPECT_EQ(tuple3(data->GetPointData()->GetArray("u"), offset + a), f(p.control_point(a)));
    }
    offset += p.num_points();
  }
  // Net lines join neighbours in the net: every line's consecutive points differ in one index.
  auto ids = vtkSmartPointer<vtkIdList>::New();
  data->GetCellPoints(0, ids);
  EXPECT_EQ(ids->GetNumberOfIds(), patches[0].num_points(0));
  EXPECT_EQ(ids->GetId(1) - ids->GetId(0), 1);
}

TEST(VtkOutput, MarkersCarryResiduals) {
  MarkerData m;
  m.positions = {{0, 0, 0}, {1, 2, 3}};
  m.cases.push_back({"L1", {{1, 0, 0}, {0, 3, 0}}, {{0.5, 0, 0}, {0, 0, 4}}});
  const fs::path path = temp_dir("markers") / "markers.vtp";
  write_markers_vtp(path, m);
  const auto data = read_vtp(path);
  ASSERT_EQ(data->GetNumberOfPoints(), 2);
  EXPECT_EQ(data->GetNumberOfVerts(), 2);
  EXPECT_EQ(tuple3(data->GetPointData()->GetArray("residual_L1"), 0), Vector3d(0.5, 0, 0));
  EXPECT_EQ(data->GetPointData()->GetArray("residual_magnitude_L1")->GetTuple1(1), 5.0);
  EXPECT_EQ(tuple3(data->GetPointData()->GetArray("measured_L1"), 1), Vector3d(0, 3, 0));
}

TEST(VtkOutput, SceneOpensAsOneMultiblock) {
  std::mt19937 rng(5);
  VtkScene scene;
  scene.patches = {testing::random_patch(rng, 2, 2, true), testing::random_patch(rng, 2, 3, false)};
  scene.fields.control.push_back(
      affine_field("displacement_L1", scene.patches, random_affine(rng)));
  scene.network = triangle_network();
  scene.markers = MarkerData{{{0, 0, 0}}, {{"L1", {{1, 1, 1}}, {{1, 1, 0}}}}};
  const fs::path dir = temp_dir("scene");
  const auto files = write_vtk_scene(dir / "result.vtm", scene);
  ASSERT_EQ(files.size(), 6u);
  EXPECT_EQ(files.back(), dir / "result.vtm");
  for (const fs::path& f : files) EXPECT_TRUE(fs::exists(f)) << f;

  auto reader = vtkSmartPointer<vtkXMLMultiBlockDataReader>::New();
  reader->SetFileName((dir / "result.vtm").c_str());
  reader->Update();
  auto* blocks = vtkMultiBlockDataSet::SafeDownCast(reader->GetOutput());
  ASSERT_NE(blocks, nullptr);
  ASSERT_EQ(blocks->GetNumberOfBlocks(), 5u);
  const std::vector<std::string> names = {"geometry", "geometry_bezier", "control_net", "springs",
                                          "markers"};
  for (unsigned b = 0; b < 5; ++b) {
    EXPECT_EQ(blocks->GetMetaData(b)->Get(vtkCompositeDataSet::NAME()), names[b]);
    ASSERT_NE(blocks->GetBlock(b), nullptr) << names[b];
  }
  EXPECT_EQ(vtkPolyData::SafeDownCast(blocks->GetBlock(3))->GetNumberOfLines(), 3);
  EXPECT_NE(vtkUnstructuredGrid::SafeDownCast(blocks->GetBlock(1))
                ->GetPointData()
                ->GetArray("displacement_L1"),
            nullptr);
}

TEST(VtkOutput, TimeSeriesFramesAreDeformedNetworks) {
  const analysis::SpringNetwork n = triangle_network();
  const fs::path dir = temp_dir("pvd");
  SpringTimeSeriesWriter series(dir / "dynamics.pvd", n);
  for (int f = 0; f < 3; ++f) {
    std::vector<Vector3d> u(3, Vector3d(0.01 * f, 0, 0));
    series.add_frame(0.5 * f, u, u);
  }
  EXPECT_THROW(series.add_frame(0.5, std::vector<Vector3d>(3, Vector3d::Zero())),
               std::invalid_argument);
  series.finish();
  std::ifstream in(dir / "dynamics.pvd");
  std::stringstream text;
  text << in.rdbuf();
  const std::string pvd = text.str();
  const std::regex entry("timestep=\"([^\"]+)\"[^>]*file=\"([^\"]+)\"");
  std::vector<std::pair<double, std::string>> entries;
  for (auto it = std::sregex_iterator(pvd.begin(), pvd.end(), entry); it != std::sregex_iterator();
       ++it)
    entries.emplace_back(std::stod((*it)[1]), (*it)[2]);
  ASSERT_EQ(entries.size(), 3u);
  EXPECT_EQ(entries[2].first, 1.0);
  const auto frame = read_vtp(dir / entries[2].second);
  Vector3d x;
  frame->GetPoint(1, x.data());
  EXPECT_NEAR((x - Vector3d(1.02, 0, 0)).norm(), 0.0, 1e-15);
  EXPECT_EQ(tuple3(frame->GetPointData()->GetArray("velocity"), 2), Vector3d(0.02, 0, 0));
}

}  // namespace
}  // namespace isospring::io
