// The example program (examples/mujoco/step_scene.c) on an exported scene with runtime terms:
// it attaches them and steps; a scene whose model.json is missing is refused with its path.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "isospring/fitting/spring_mesh.hpp"
#include "isospring/fitting/thesis_experiments.hpp"
#include "isospring/io/export_mjcf.hpp"
#include "run_program.hpp"

namespace isospring {
namespace {
namespace fs = std::filesystem;

TEST(MujocoExample, StepsAnExportedSceneWithItsTerms) {
  fitting::SpringMeshOptions mesh;
  mesh.volume_terms = true;
  mesh.shear_terms = true;
  analysis::SpringNetwork n =
      fitting::build_spring_mesh(fitting::thesis_cube(3).problem, mesh).network;
  n.masses.assign(n.positions.size(), 0.1);
  n.fixed.assign(n.positions.size(), false);
  for (size_t p = 0; p < n.positions.size(); ++p) n.fixed[p] = n.positions[p].x() < 1e-9;
  for (analysis::Spring& s : n.springs) s.stiffness = 1e3;
  for (analysis::VolumeTerm& t : n.volumes) t.modulus = 1e3;
  const fs::path dir =
      fs::temp_directory_path() / ("isospring_test_mujoco_example-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  io::write_mjcf(dir / "cube.xml", n, {});
  const testing::ProgramResult run = testing::run_program(
      std::string(ISOSPRING_MUJOCO_STEP) + " " + (dir / "cube.xml").string() + " 200 26 0 0 -1");
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("runtime terms attached through mjcb_passive"), std::string::npos)
      << run.output;
  EXPECT_NE(run.output.find("200 steps of"), std::string::npos) << run.output;

  fs::remove(dir / "cube.isospring.json");
  const testing::ProgramResult missing =
      testing::run_program(std::string(ISOSPRING_MUJOCO_STEP) + " " + (dir / "cube.xml").string());
  EXPECT_EQ(missing.exit_code, 1) << missing.output;
  EXPECT_NE(missing.output.find("cube.isospring.json: cannot open the model file"),
            std::string::npos)
      << missing.output;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace isospring
