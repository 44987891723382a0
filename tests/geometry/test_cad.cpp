// CAD import/export: test parts made with OpenCascade, the third-party files of ../shared/cad,
// exact round trips and bad files.
#include <gtest/gtest.h>
#include <unistd.h>  // getpid: CTest runs tests in parallel processes

#include <BRepBuilderAPI_Transform.hxx>
#include <BRepGProp.hxx>
#include <Eigen/Geometry>
#include <GProp_GProps.hxx>
#include <Interface_Static.hxx>
#include <STEPControl_Controller.hxx>
#include <STEPControl_Writer.hxx>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <gp_Ax1.hxx>
#include <gp_Trsf.hxx>
#include <random>

#include "cad_test_parts.hpp"
#include "isospring/geometry/cad.hpp"
#include "isospring/geometry/construction.hpp"
#include "isospring/geometry/measure.hpp"
#include "isospring/geometry/point_locator.hpp"
#include "isospring/geometry/primitives.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::geometry {
namespace {

namespace fs = std::filesystem;

fs::path temp_folder() {
  const fs::path dir =
      fs::temp_directory_path() / (std::string("isospring_test_cad-") + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

void write_step(const TopoDS_Shape& shape, const fs::path& file) {
  STEPControl_Controller::Init();
  Interface_Static::SetCVal("xstep.cascade.unit", "M");
  Interface_Static::SetCVal("write.step.unit", "M");
  STEPControl_Writer writer;
  ASSERT_EQ(writer.Transfer(shape, STEPControl_AsIs), IFSelect_RetDone);
  ASSERT_EQ(writer.Write(file.string().c_str()), IFSelect_RetDone);
}

double occt_volume(const TopoDS_Shape& shape) {
  GProp_GProps props;
  BRepGProp::VolumeProperties(shape, props, 1e-9);
  return props.Mass();
}

TEST(CadParts, RegeneratedPartsMatchTheCommittedCopies) {
  const bool write_examples = std::getenv("ISOSPRING_WRITE_EXAMPLE_CAD") != nullptr;
  const fs::path examples = fs::path(ISOSPRING_SOURCE_DIR) / "examples" / "cad";
  for (const auto& [name, part] : test::cad_test_parts()) {
    const fs::path file = (write_examples ? examples : temp_folder()) / name;
    write_step(part.shape, file);
    EXPECT_NEAR(occt_volume(part.shape) / part.exact_volume, 1.0, 1e-9) << name;
    const CadModel fresh = read_cad(file);
    EXPECT_NEAR(fresh.volume / part.exact_volume, 1.0, 1e-9) << name;
    ASSERT_TRUE(fs::exists(examples / name)) << "run with ISOSPRING_WRITE_EXAMPLE_CAD=1";
    const CadModel committed = read_cad(examples / name);
    EXPECT_EQ(committed.faces, fresh.faces) << name;
    EXPECT_NEAR(committed.volume, fresh.volume, 1e-12 * fresh.volume) << name;
    EXPECT_NEAR(committed.area, fresh.area, 1e-12 * fresh.area) << name;
  }
}

TEST(CadImport, HexahedralBlockIsOneExactVolumePatch) {
  const fs::path file = temp_folder() / "block.step";
  write_step(test::cad_test_parts()["block.step"].shape, file);
  const CadModel model = read_cad(file);
  EXPECT_EQ(model.faces, 6);
  ASSERT_EQ(model.volume_patches.size(), 1u);
  EXPECT_NEAR(measure(model.volume_patches) / 4e-5, 1.0, 1e-13);
  EXPECT_GT(jacobian_range(model.volume_patches[0]).min, 0.0);
  EXPECT_EQ(cad_patches(model).size(), 1u);
  // Axis-aligned block: u along x, v along y, w along z from the smallest corner, whatever the
  // vertex order in the file (the case-file sides u0/u1 then mean x = 0 / x = 0.1, as for `box`).
  const nurbs::Patch& volume = model.volume_patches[0];
  EXPECT_LT(volume.point({0, 0, 0}).norm(), 1e-15);
  EXPECT_LT((volume.point({1, 0, 0}) - Eigen::Vector3d(0.1, 0, 0)).norm(), 1e-15);
  EXPECT_LT((volume.point({0, 1, 0}) - Eigen::Vector3d(0, 0.02, 0)).norm(), 1e-15);
  EXPECT_LT((volume.point({0, 0, 1}) - Eigen::Vector3d(0, 0, 0.02)).norm(), 1e-15);
  // A rotated copy keeps a right-handed numbering (positive Jacobian) with u nearest to x.
  gp_Trsf rotation;
  rotation.SetRotation(gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(1, 2, 3)), 0.7);
  const fs::path turned = temp_folder() / "block_turned.step";
  write_step(BRepBuilderAPI_Transform(test::cad_test_parts()["block.step"].shape, rotation).Shape(),
             turned);
  const CadModel turned_model = read_cad(turned);
  ASSERT_EQ(turned_model.volume_patches.size(), 1u);
  EXPECT_GT(jacobian_range(turned_model.volume_patches[0]).min, 0.0);
  EXPECT_NEAR(measure(turned_model.volume_patches) / 4e-5, 1.0, 1e-12);
  // Every face is a natural rectangle, oriented outwards: the divergence theorem with the
  // face patches gives the volume (sum over faces of integral x . n / 3).
  ASSERT_EQ(model.face_patches.size(), 6u);
  double flux = 0.0;
  for (const auto& face : model.face_patches) {
    const nurbs::PatchDerivatives d =
        face.derivatives({0.5 * (face.param_min(0) + face.param_max(0)),
                          0.5 * (face.param_min(1) + face.param_max(1)), 0});
    const Eigen::Vector3d n = d.first.col(0).cross(d.first.col(1)).normalized();
    flux += d.point.dot(n) * measure(face) / 3.0;  // planar faces: x . n is constant
  }
  EXPECT_NEAR(flux / 4e-5, 1.0, 1e-12);
  // Planar faces extruded along the normal.
  const auto slabs = cad_patches(model, 0.001, {0, 1});
  EXPECT_NEAR(measure(slabs),
              0.001 * (measure(model.face_patches[0]) + measure(model.face_patches[1])), 1e-15);
}

TEST(CadImport, TorusFaceIsANaturalRationalPatch) {
  const fs::path file = temp_folder() / "torus.step";
  write_step(test::cad_test_parts()["torus.step"].shape, file);
  const CadModel model = read_cad(file);
  ASSERT_EQ(model.face_patches.size(), 1u);
  const double R = 0.0875, r = 0.0375;
  EXPECT_NEAR(measure(model.face_patches) / (4 * M_PI * M_PI * R * r), 1.0, 1e-12);
  std::mt19937 rng(2);
  const nurbs::Patch& p = model.face_patches[0];
  for (int n = 0; n < 20; ++n) {
    const nurbs::Param u{
        std::uniform_real_distribution<double>(p.param_min(0), p.param_max(0))(rng),
        std::uniform_real_distribution<double>(p.param_min(1), p.param_max(1))(rng), 0};
    const Eigen::Vector3d x = p.point(u);
    EXPECT_NEAR(std::hypot(std::hypot(x.x(), x.y()) - R, x.z()), r, 1e-15);
  }
  EXPECT_THROW(cad_patches(model, 0.01), nurbs::InputError);  // curved face: no exact extrusion
}

TEST(CadImport, TrimmedFacesWithHolesAreCut) {
  const fs::path file = temp_folder() / "plate.step";
  write_step(test::cad_test_parts()["plate_with_holes.step"].shape, file);
  const CadModel model = read_cad(file);
  int trimmed = 0;
  for (const auto& f : model.face_reports)
    if (!f.natural) {
      ++trimmed;
      EXPECT_EQ(f.split, 15) << f.note;  // 7 rectangles and a ring of 4 around each hole
      EXPECT_TRUE(f.note.empty()) << f.note;
    }
  EXPECT_EQ(trimmed, 2);  // top and bottom have holes; the hole walls are whole cylinders
  EXPECT_EQ(cad_patches(model).size(), 15u);  // the solid: a prism of the cut face
  EXPECT_EQ(cad_patches(model, 0.0, {0, 1, 2, 3, 4, 5, 6, 7}).size(), 6u + 2 * 15u);
  EXPECT_EQ(describe(model).find("NOT usable"), std::string::npos);
}

// Third-party files (../shared/cad): units, areas and volumes against OpenCascade's README values.
TEST(CadImport, SharedFilesInMetres) {
  const fs::path dir = fs::path(ISOSPRING_SHARED_DIR) / "cad";
  if (!fs::exists(dir / "torus_ap203.stp")) GTEST_SKIP() << "../shared/cad is not present";
  const CadModel torus = read_cad(dir / "torus_ap203.stp");
  EXPECT_EQ(torus.file_unit, "millimetre");
  EXPECT_NEAR(torus.bbox_max.x(), 0.25, 1e-6);
  ASSERT_EQ(torus.face_patches.size(), 1u);
  EXPECT_NEAR(measure(torus.face_patches) / 3.947841760e-01, 1.0, 1e-6);
  EXPECT_NEAR(measure(torus.face_patches) / (4 * M_PI * M_PI * 0.2 * 0.05), 1.0, 1e-12);

  const CadModel bracket = read_cad(dir / "l_bracket_caxif.stp");
  EXPECT_EQ(bracket.faces, 16);
  EXPECT_NEAR(bracket.volume / 9.685840574e-05, 1.0, 1e-6);
  EXPECT_NEAR(bracket.area / 2.462831929e-02, 1.0, 1e-6);
  double natural_area = 0.0, natural_occt = 0.0;
  for (size_t i = 0; i < bracket.face_patches.size(); ++i) {
    natural_area += measure(bracket.face_patches[i]);
    natural_occt += bracket.face_reports[static_cast<size_t>(bracket.patch_face[i])].area;
  }
  EXPECT_EQ(bracket.face_patches.size(), 10u);  // 8 half-cylinders + 2 rectangles
  EXPECT_NEAR(natural_area / natural_occt, 1.0, 1e-6);

  const CadModel cubes = read_cad(dir / "cube_cylinder_cadquery.step");
  EXPECT_EQ(cubes.solids, 2);
  EXPECT_NEAR(cubes.bbox_min.x(), -0.010, 1e-6);
  EXPECT_NEAR(cubes.bbox_max.x(), 0.015, 1e-6);
  EXPECT_NEAR(cubes.volume / 1.785398163e-06, 1.0, 1e-6);

  const CadModel iges = read_cad(dir / "cylinder_catia.igs");
  EXPECT_EQ(iges.faces, 4);
  EXPECT_NEAR(iges.area / 4.712388981e-02, 1.0, 1e-6);
  EXPECT_NEAR(iges.bbox_max.x(), 0.1, 1e-6);
}

TEST(CadExport, RoundTripReproducesTheGeometry) {
  Patches patches = disk_five_patch(0.5);
  for (const auto& p : hollow_sphere_sector(1.0, 2.0)) patches.push_back(p);
  patches.push_back(transformed(box(1, 2, 3)[0], Eigen::Matrix3d::Identity(), {5, 0, 0}));
  for (const char* name : {"roundtrip.step", "roundtrip.igs"}) {
    const fs::path file = temp_folder() / name;
    const CadWriteSummary summary = write_cad(file, patches);
    EXPECT_EQ(summary.solids, 2) << name;  // the sphere sector and the box, closed
    const CadModel back = read_cad(file);
    // Surfaces in writing order: 5 disk patches, then 6 sides per volume.
    std::vector<nurbs::Patch> written(patches.begin(), patches.begin() + 5);
    for (size_t v = 5; v < patches.size(); ++v)
      for (int dir = 0; dir < 3; ++dir)
        for (int end = 0; end < 2; ++end) written.push_back(boundary_side(patches[v], dir, end));
    // The sector's side at polar angle 0 collapses onto the z axis (zero area): sewing the solid
    // removes that degenerate face, so one face fewer comes back; its samples lie on the axis,
    // an edge of the faces that remain (checked below like every other face).
    ASSERT_EQ(back.face_patches.size(), written.size() - 1) << name;
    // Same surfaces (the IGES writer may reorder and reparametrise faces): samples of every
    // written patch lie on the read faces, and the total areas agree. The files carry 15
    // significant digits, so areas agree to ~1e-12 relative.
    const PointLocator on_read(back.face_patches);
    std::mt19937 rng(4);
    for (size_t f = 0; f < written.size(); ++f)
      for (int n = 0; n < 10; ++n) {
        const nurbs::Param u{std::uniform_real_distribution<double>(0, 1)(rng),
                             std::uniform_real_distribution<double>(0, 1)(rng), 0};
        EXPECT_LT(on_read.locate(written[f].point(u)).distance, 1e-9) << name << " face " << f;
      }
    EXPECT_NEAR(measure(back.face_patches) / measure(written), 1.0, 1e-9) << name;
  }
}

// volume patches go out as closed solids (six sides sewn, outward normals), so a CAD
// reader finds solids and their volume. OpenCascade's own volume of the solids read back
// (BRepGProp, independent of our quadrature) equals the patches' volume, for an exact box and a
// curved rational tube sector, in both formats; `import --solids` reading them back as volume
// patches is checked end to end (FileReports / CadRoundTrip in tests/apps).
TEST(CadExport, VolumesAreWrittenAsClosedSolids) {
  // OpenCascade integrates the planar box exactly; for the rational tube its default volume
  // integration (BRepGProp, no accuracy target) is good to ~1e-8 only, hence 1e-7 there. The
  // volume patch rebuilt from the solid read back (what `import --solids` does) has the written
  // volume to 1e-9 in both cases (our Gauss quadrature).
  const std::vector<std::pair<Patches, double>> parts{{box(0.01, 0.02, 0.03), 1e-12},
                                                      {tube_sector(0.5, 0.8, 2.0), 1e-7}};
  for (const auto& [volumes, tolerance] : parts)
    for (const char* name : {"solids.step", "solids.igs"}) {
      const fs::path file = temp_folder() / name;
      const CadWriteSummary written = write_cad(file, volumes);
      EXPECT_EQ(written.solids, static_cast<int>(volumes.size())) << name;
      EXPECT_TRUE(written.notes.empty()) << name;
      EXPECT_EQ(written.faces, 6 * static_cast<int>(volumes.size())) << name;
      const CadModel back = read_cad(file);
      EXPECT_EQ(back.solids, static_cast<int>(volumes.size())) << name;
      EXPECT_NEAR(back.volume / measure(volumes), 1.0, tolerance) << name;
      const Patches rebuilt = cad_solid_patches(back, {0});
      ASSERT_EQ(rebuilt.size(), 1u) << name;
      EXPECT_NEAR(measure(rebuilt) / measure(volumes), 1.0, 1e-9) << name;
    }
}

TEST(CadExport, WritesAtomically) {
  // Complete: the part appears under its name and no temporary file is left beside it.
  const fs::path dir = temp_folder() / "atomic";
  fs::remove_all(dir);
  fs::create_directories(dir);
  write_cad(dir / "box.step", box(1, 2, 3));
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir))
    names.push_back(entry.path().filename().string());
  EXPECT_EQ(names, std::vector<std::string>{"box.step"});
  // Failed: an existing part is kept untouched when a new write cannot complete (a folder
  // stands where the temporary file would go, so OpenCascade's writer fails).
  const std::string before = [&] {
    std::ifstream in(dir / "box.step");
    return std::string(std::istreambuf_iterator<char>(in), {});
  }();
  fs::create_directories(dir / ".box.step.isospring-tmp.step");
  EXPECT_ANY_THROW(write_cad(dir / "box.step", box(2, 2, 2)));
  std::ifstream in(dir / "box.step");
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), before);
  fs::remove_all(dir);
}

TEST(CadImport, BadFilesAreInputErrors) {
  const fs::path dir = temp_folder();
  auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
    return dir / name;
  };
  EXPECT_THROW(read_cad(dir / "missing.step"), nurbs::InputError);
  EXPECT_THROW(read_cad(write("empty.step", "")), nurbs::InputError);
  EXPECT_THROW(read_cad(write("text.step", "hello, not a part\n")), nurbs::InputError);
  EXPECT_THROW(read_cad(write("part.obj", "v 0 0 0\n")), nurbs::InputError);
  EXPECT_THROW(read_cad(write("text.igs", "garbage\n")), nurbs::InputError);
  // A STEP file cut in half.
  const fs::path whole = dir / "whole.step";
  write_step(test::cad_test_parts()["block.step"].shape, whole);
  std::ifstream in(whole);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_THROW(read_cad(write("truncated.step", text.substr(0, text.size() / 2))),
               nurbs::InputError);
  EXPECT_THROW(write_cad(dir / "x.obj", box(1, 1, 1)), nurbs::InputError);
}

}  // namespace
}  // namespace isospring::geometry
