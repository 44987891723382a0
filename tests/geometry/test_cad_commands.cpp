// End to end: `isospring import` and `isospring export-step` on the committed block and tube.
#include <gtest/gtest.h>
#include <unistd.h>  // getpid: CTest runs tests in parallel processes

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "isospring/geometry/cad.hpp"
#include "isospring/geometry/measure.hpp"
#include "isospring/io/patch_file.hpp"

namespace isospring::geometry {
namespace {

namespace fs = std::filesystem;

int run(const std::string& arguments) {
  const std::string command =
      std::string(ISOSPRING_EXECUTABLE) + " " + arguments + " >/dev/null 2>&1";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(CadCommands, ImportThenExportStep) {
  if (!fs::exists(ISOSPRING_EXECUTABLE)) GTEST_SKIP() << "build the isospring program first";
  const fs::path dir = fs::temp_directory_path() /
                       (std::string("isospring_test_cad_commands-") + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path block = fs::path(ISOSPRING_SOURCE_DIR) / "examples" / "cad" / "block.step";
  ASSERT_EQ(run("import " + block.string() + " -o " + (dir / "block.json").string()), 0);
  const auto patches = io::read_patch_file(dir / "block.json");
  ASSERT_EQ(patches.size(), 1u);
  EXPECT_NEAR(measure(patches) / 4e-5, 1.0, 1e-13);
  ASSERT_EQ(
      run("export-step " + (dir / "block.json").string() + " -o " + (dir / "out.step").string()),
      0);
  const CadModel back = read_cad(dir / "out.step");
  EXPECT_EQ(back.face_patches.size(), 6u);
  EXPECT_NEAR(measure(back.face_patches) / 0.0088, 1.0, 1e-12);
  // IGES keeps metres too (the writer once divided coordinates by 1000 under the unit flag M).
  ASSERT_EQ(
      run("export-step " + (dir / "block.json").string() + " -o " + (dir / "out.igs").string()), 0);
  const CadModel iges = read_cad(dir / "out.igs");
  EXPECT_EQ(iges.face_patches.size(), 6u);
  EXPECT_NEAR(measure(iges.face_patches) / 0.0088, 1.0, 1e-12);
  EXPECT_NEAR(iges.bbox_max.x(), 0.1, 1e-6);  // OCCT pads the box by the 1e-7 tolerance
  // The tube (a solid of revolution) imports as four exact quarter volumes.
  const fs::path tube = fs::path(ISOSPRING_SOURCE_DIR) / "examples" / "cad" / "tube.step";
  ASSERT_EQ(run("import " + tube.string() + " -o " + (dir / "tube.json").string()), 0);
  const auto quarters = io::read_patch_file(dir / "tube.json");
  ASSERT_EQ(quarters.size(), 4u);
  EXPECT_NEAR(measure(quarters) / (M_PI * (0.02 * 0.02 - 0.015 * 0.015) * 0.1), 1.0, 1e-12);
  // Bad input: exit status 1 (InputError), the input untouched.
  std::ofstream(dir / "bad.step") << "not a step file\n";
  EXPECT_EQ(run("import " + (dir / "bad.step").string() + " -o " + (dir / "bad.json").string()), 1);
  EXPECT_FALSE(fs::exists(dir / "bad.json"));
  EXPECT_EQ(run("export-step " + (dir / "block.json").string() + " -o " + (dir / "x.obj").string()),
            1);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace isospring::geometry
