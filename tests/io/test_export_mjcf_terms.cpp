// The MJCF export of a model with volume, shear and strain-point terms: the scene keeps the
// springs as tendons and names the model.json beside it, which write_mjcf writes and which reads
// back as the same network; the automatic time step bounds the whole stiffness (Gershgorin on
// M^-1 K, checked against the exact largest eigenvalue). MuJoCo running such a scene with the
// runtime is tests/mujoco.
#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Eigenvalues>
#include <filesystem>
#include <regex>

#include "isospring/analysis/spring_mechanics.hpp"
#include "isospring/analysis/spring_volume.hpp"
#include "isospring/io/atomic_file.hpp"
#include "isospring/io/export_mjcf.hpp"
#include "isospring/io/model_file.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::io {
namespace {
namespace fs = std::filesystem;

// Two unit cells side by side along x, x = 0 face fixed, edge springs, a volume and a shear
// term per cell and one strain point over the free corners.
analysis::SpringNetwork two_cells() {
  analysis::SpringNetwork n;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 3; ++i) {
        n.positions.emplace_back(0.1 * i, 0.1 * j, 0.1 * k);
        n.masses.push_back(0.01 * (1 + i));
        n.fixed.push_back(i == 0);
      }
  const int count = static_cast<int>(n.positions.size());
  for (int a = 0; a < count; ++a)
    for (int b = a + 1; b < count; ++b) {
      const double l = (n.positions[size_t(b)] - n.positions[size_t(a)]).norm();
      if (l < 0.1 + 1e-12) n.springs.push_back({a, b, 500.0 + 10 * a, 0.1, l, 0});
    }
  for (int cell = 0; cell < 2; ++cell)
    for (auto kind : {analysis::CellEnergy::kVolume, analysis::CellEnergy::kShear}) {
      analysis::VolumeTerm t;
      t.kind = kind;
      for (int a = 0; a < 8; ++a)
        t.particles[size_t(a)] = cell + (a & 1) + 3 * ((a >> 1) & 1) + 6 * ((a >> 2) & 1);
      t.rest_volume = analysis::rest_cell_volume(n, t);
      t.modulus = kind == analysis::CellEnergy::kVolume ? 4e4 : 2e4;
      n.volumes.push_back(t);
    }
  analysis::VolumeTerm point;
  point.kind = analysis::CellEnergy::kShear;
  point.points = {1, 2, 4, 5};
  point.gradients = {{-5, 0, 0}, {5, -5, 0}, {0, 5, 1}, {0, 0, -1}};
  point.rest_volume = 1e-3;
  point.modulus = 1e4;
  n.volumes.push_back(point);
  return n;
}

TEST(ExportMjcfTerms, SceneNamesTheModelBesideItWhichReadsBackTheSame) {
  const analysis::SpringNetwork n = two_cells();
  const fs::path dir =
      fs::temp_directory_path() / ("isospring_test_mjcf_terms-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  MjcfOptions options;
  options.particle_damping_rate = 3.0;
  write_mjcf(dir / "scene.xml", n, options);
  const std::string xml = read_text_file(dir / "scene.xml", "scene");
  EXPECT_NE(xml.find("<text name=\"isospring_model\" data=\"scene.isospring.json\"/>"),
            std::string::npos);
  // Springs stay tendons; the joints of particle 2 (mass 0.03) carry 3 x 0.03 of damping.
  const std::regex spatial("<spatial ");
  EXPECT_EQ(
      std::distance(std::sregex_iterator(xml.begin(), xml.end(), spatial), std::sregex_iterator()),
      static_cast<long>(n.springs.size()));
  std::smatch damping;
  ASSERT_TRUE(std::regex_search(
      xml, damping,
      std::regex("<joint name=\"particle_2_x\" axis=\"1 0 0\" damping=\"([^\"]*)\"")));
  EXPECT_NEAR(std::stod(damping[1].str()), 3.0 * n.masses[2], 1e-15);
  const SpringModel beside = read_model_json(dir / "scene.isospring.json");
  ASSERT_EQ(beside.network.volumes.size(), n.volumes.size());
  const Eigen::MatrixXd k = Eigen::MatrixXd(analysis::rest_stiffness(n));
  EXPECT_EQ((Eigen::MatrixXd(analysis::rest_stiffness(beside.network)) - k).norm(), 0.0);
  // The document alone (no file named for the terms) is refused with the way out.
  try {
    (void)mjcf_document(n);
    FAIL() << "a model with terms was exported without its runtime model";
  } catch (const nurbs::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("passive-force callback"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

// dt = 0.2 x 2 / omega_max with omega_max^2 bounded by Gershgorin: the exact largest eigenvalue
// of M^-1 K (dense, free DOFs) must lie at or below the bound, and not far below (the bound of
// a row sum is within the stencil's size of the truth).
TEST(ExportMjcfTerms, TimeStepBoundsTheWholeStiffness) {
  const analysis::SpringNetwork n = two_cells();
  const double bound = std::pow(0.4 / suggested_timestep(n), 2);
  const Eigen::MatrixXd k = Eigen::MatrixXd(analysis::rest_stiffness(n));
  const Eigen::VectorXd m = analysis::mass_diagonal(n);
  std::vector<int> free;
  for (int d = 0; d < k.rows(); ++d)
    if (!n.fixed[size_t(d / 3)]) free.push_back(d);
  Eigen::MatrixXd a(free.size(), free.size());
  for (size_t r = 0; r < free.size(); ++r)
    for (size_t c = 0; c < free.size(); ++c)
      a(Eigen::Index(r), Eigen::Index(c)) =
          k(free[r], free[c]) / std::sqrt(m[free[r]] * m[free[c]]);
  const double largest = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(a).eigenvalues().maxCoeff();
  EXPECT_LE(largest, bound * (1 + 1e-12));
  EXPECT_GT(largest, bound / 30);
  // Without the terms the springs' own bound applies, and it is lower.
  analysis::SpringNetwork springs = n;
  springs.volumes.clear();
  EXPECT_GT(suggested_timestep(springs), suggested_timestep(n));
}

}  // namespace
}  // namespace isospring::io
