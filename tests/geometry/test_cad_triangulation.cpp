// Display triangulations of CAD parts, trimmed faces included: the triangles cover every face
// (total area against OpenCascade's BRepGProp) and are oriented outwards (the divergence theorem
// over the triangles gives the solid's volume), and `isospring import --display` writes them.
#include <gtest/gtest.h>
#include <unistd.h>  // getpid: CTest runs tests in parallel processes

#include <Eigen/Geometry>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "isospring/geometry/cad.hpp"
#include "isospring/geometry/cad_triangulation.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::geometry {
namespace {

namespace fs = std::filesystem;

fs::path example(const std::string& name) {
  return fs::path(ISOSPRING_SOURCE_DIR) / "examples" / "cad" / name;
}

struct Measures {
  double area = 0.0, volume = 0.0;
};

Measures measures(const CadTriangulation& mesh) {
  Measures m;
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d &a = mesh.points[static_cast<size_t>(t[0])],
                          &b = mesh.points[static_cast<size_t>(t[1])],
                          &c = mesh.points[static_cast<size_t>(t[2])];
    m.area += 0.5 * (b - a).cross(c - a).norm();
    m.volume += a.dot(b.cross(c)) / 6.0;  // signed tetrahedron with the origin
  }
  return m;
}

TEST(CadTriangulation, CoversTrimmedFacesAndPointsOutwards) {
  // The bracket and the plate with holes have faces with holes and 6-edge outlines (cut into
  // patches for the analysis); the display shows the trimmed faces themselves. Curved faces are cut
  // by chords: a face of radius r meshed with sagitta d loses about d / (3 r) of its area (chord
  // angle^2 / 6, with angle^2 = 8 d / r) and up to twice that of its volume. With d = 1e-5 of the
  // diagonal: the tube (d = 1.1e-6 m, r >= 15 mm) loses <= 5e-5; the bracket and the plate (d
  // <= 2.4e-6 m, holes of r = 4 and 5 mm) lose <= 2e-4 of their hole walls, which are under 5 % of
  // their area and volume. Hence 1e-4 relative in total.
  for (const char* name : {"bracket.step", "plate_with_holes.step", "tube.step", "block.step"}) {
    const CadModel model = read_cad(example(name));
    const CadTriangulation mesh = triangulate_cad(example(name), 1e-5);
    ASSERT_FALSE(mesh.triangles.empty()) << name;
    ASSERT_EQ(mesh.triangles.size(), mesh.triangle_face.size());
    const std::set<int> faces(mesh.triangle_face.begin(), mesh.triangle_face.end());
    EXPECT_EQ(static_cast<int>(faces.size()), model.faces) << name << ": every face displayed";
    const Measures m = measures(mesh);
    EXPECT_NEAR(m.area / model.area, 1.0, 1e-4) << name;
    EXPECT_NEAR(m.volume / model.volume, 1.0, 1e-4) << name << ": outward orientation";
  }
  // A planar block is meshed exactly.
  const Measures block = measures(triangulate_cad(example("block.step")));
  EXPECT_NEAR(block.volume / 4e-5, 1.0, 1e-12);
}

TEST(CadTriangulation, BadInputIsAnInputError) {
  EXPECT_THROW(triangulate_cad(example("block.step"), 0.0), nurbs::InputError);
  EXPECT_THROW(triangulate_cad(example("missing.step")), nurbs::InputError);
}

TEST(CadTriangulation, ImportWritesTheDisplayFile) {
  if (!fs::exists(ISOSPRING_EXECUTABLE)) GTEST_SKIP() << "build the isospring program first";
  const fs::path dir = fs::temp_directory_path() /
                       (std::string("isospring_test_cad_display-") + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  // The bracket's faces (L sections and faces with a hole cut into patches) become patches; the
  // display is written first, so it is there even when a face cannot be used.
  const std::string command =
      std::string(ISOSPRING_EXECUTABLE) + " import " + example("bracket.step").string() + " -o " +
      (dir / "b.json").string() + " --display " + (dir / "b.vtp").string() + " >/dev/null 2>&1";
  const int status = std::system(command.c_str());
  EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 0);
  EXPECT_TRUE(fs::exists(dir / "b.json"));
  ASSERT_TRUE(fs::exists(dir / "b.vtp"));
  std::ifstream in(dir / "b.vtp");
  std::stringstream text;
  text << in.rdbuf();
  const size_t triangles = triangulate_cad(example("bracket.step")).triangles.size();
  EXPECT_NE(text.str().find("NumberOfPolys=\"" + std::to_string(triangles) + "\""),
            std::string::npos);
  EXPECT_NE(text.str().find("Name=\"face\""), std::string::npos);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace isospring::geometry
