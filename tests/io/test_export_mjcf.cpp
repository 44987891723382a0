// MuJoCo export. The exported file is loaded and simulated by MuJoCo (when it is installed): a
// braced lattice, fixed on one face and loaded on the other, is let settle with damping and its
// static displacements are compared with the linear spring model K u = f solved here with Eigen
// (small loads: strains ~1e-4, so geometric nonlinearity is ~1e-4 relative).
#include <gtest/gtest.h>
#include <unistd.h>  // getpid: CTest runs tests in parallel processes

#include <Eigen/Dense>
#include <cmath>
#include <filesystem>
#include <optional>
#include <regex>
#include <sstream>

#include "isospring/io/export_mjcf.hpp"
#include "isospring/nurbs/error.hpp"

#ifdef ISOSPRING_HAVE_MUJOCO
#include <mujoco/mujoco.h>
#endif

namespace isospring::io {
namespace {
namespace fs = std::filesystem;
using Eigen::Vector3d;

/// An nx x ny x nz lattice of unit cubes with edges, face and body diagonals (stable), the x = 0
/// face fixed. Stiffness and masses vary so that a mix-up of indices would show.
analysis::SpringNetwork braced_lattice(int nx, int ny, int nz, double h) {
  analysis::SpringNetwork n;
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        n.positions.emplace_back(h * i, h * j, h * k);
        n.masses.push_back(0.01 * (1 + (i + 2 * j + 3 * k) % 4));
        n.fixed.push_back(i == 0);
      }
  const int count = static_cast<int>(n.positions.size());
  for (int a = 0; a < count; ++a)
    for (int b = a + 1; b < count; ++b) {
      const Vector3d d = n.positions[static_cast<size_t>(b)] - n.positions[static_cast<size_t>(a)];
      const Vector3d cells = (d / h).cwiseAbs();
      if (cells.maxCoeff() > 1.5) continue;  // only within one cube
      const double L = d.norm();
      analysis::Spring s;
      s.i = a;
      s.j = b;
      s.stiffness = 1000.0 * (1.0 + 0.5 * ((a + b) % 3));
      s.damping = 10.0;
      s.rest_length = L;
      s.group = static_cast<int>(std::lround(cells.sum())) - 1;
      n.springs.push_back(s);
    }
  return n;
}

/// Linear statics of the spring model at its rest state: K = sum k n n^T over springs.
std::vector<Vector3d> linear_solution(const analysis::SpringNetwork& n,
                                      const std::vector<Vector3d>& forces) {
  const int count = static_cast<int>(n.positions.size());
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(3 * count, 3 * count);
  for (const analysis::Spring& s : n.springs) {
    const Vector3d d =
        (n.positions[static_cast<size_t>(s.j)] - n.positions[static_cast<size_t>(s.i)])
            .normalized();
    const Eigen::Matrix3d k = s.stiffness * d * d.transpose();
    K.block<3, 3>(3 * s.i, 3 * s.i) += k;
    K.block<3, 3>(3 * s.j, 3 * s.j) += k;
    K.block<3, 3>(3 * s.i, 3 * s.j) -= k;
    K.block<3, 3>(3 * s.j, 3 * s.i) -= k;
  }
  std::vector<int> free;
  for (int p = 0; p < count; ++p)
    if (!n.fixed[static_cast<size_t>(p)])
      for (int c = 0; c < n.dimension; ++c) free.push_back(3 * p + c);  // 2D: in-plane only
  const int m = static_cast<int>(free.size());
  Eigen::MatrixXd Kff(m, m);
  Eigen::VectorXd f(m);
  for (int a = 0; a < m; ++a) {
    f(a) = forces[static_cast<size_t>(free[static_cast<size_t>(a)] / 3)](
        free[static_cast<size_t>(a)] % 3);
    for (int b = 0; b < m; ++b)
      Kff(a, b) = K(free[static_cast<size_t>(a)], free[static_cast<size_t>(b)]);
  }
  const Eigen::VectorXd u = Kff.ldlt().solve(f);
  std::vector<Vector3d> out(static_cast<size_t>(count), Vector3d::Zero());
  for (int a = 0; a < m; ++a)
    out[static_cast<size_t>(free[static_cast<size_t>(a)] / 3)](free[static_cast<size_t>(a)] % 3) =
        u(a);
  return out;
}

TEST(ExportMjcf, DocumentHasOneBodyPerFreeParticleAndOneTendonPerSpring) {
  const analysis::SpringNetwork n = braced_lattice(2, 1, 1, 0.05);
  const std::string xml = mjcf_document(n);
  auto count = [&](const std::string& pattern) {
    const std::regex r(pattern);
    return std::distance(std::sregex_iterator(xml.begin(), xml.end(), r), std::sregex_iterator());
  };
  long free = 0;
  for (bool f : n.fixed) free += f ? 0 : 1;
  EXPECT_EQ(count("<body "), free);
  EXPECT_EQ(count("<joint name="), 3 * free);
  EXPECT_EQ(count("<spatial "), static_cast<long>(n.springs.size()));
  EXPECT_EQ(count("<site name="), static_cast<long>(n.positions.size()));
}

// A flat (2D) model's particles slide in x and y only: gravity along z would never move them
//, so the default engine gravity of a 2D model is in its plane and a z gravity is
// refused with the fix; 3D models keep -z, and a model's own gravity wins over the default.
TEST(ExportMjcf, FlatModelsGetInPlaneGravityAndRefuseZ) {
  analysis::SpringNetwork flat = braced_lattice(2, 1, 0, 0.05);
  flat.dimension = 2;
  const analysis::SpringNetwork solid = braced_lattice(1, 1, 1, 0.05);
  EXPECT_EQ(engine_gravity(flat, Vector3d::Zero(), std::nullopt), Vector3d(0, -9.81, 0));
  EXPECT_EQ(engine_gravity(solid, Vector3d::Zero(), std::nullopt), Vector3d(0, 0, -9.81));
  EXPECT_EQ(engine_gravity(flat, Vector3d(1, 2, 0), std::nullopt), Vector3d(1, 2, 0));
  EXPECT_EQ(engine_gravity(solid, Vector3d::Zero(), Vector3d(0, 0, -1)), Vector3d(0, 0, -1));
  try {
    (void)engine_gravity(flat, Vector3d::Zero(), Vector3d(0, 0, -9.81));
    FAIL() << "a z gravity was accepted for a flat model";
  } catch (const nurbs::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--gravity 0,-9.81,0"), std::string::npos) << e.what();
  }
  MjcfOptions options;  // default gravity: -z
  EXPECT_THROW((void)mjcf_document(flat, options), nurbs::InputError);
  options.gravity = Vector3d(0, -9.81, 0);
  const std::string xml = mjcf_document(flat, options);
  std::smatch gravity;
  ASSERT_TRUE(std::regex_search(xml, gravity, std::regex("gravity=\"([^\"]*)\"")));
  std::istringstream g(gravity[1].str());
  Vector3d written;
  g >> written.x() >> written.y() >> written.z();
  EXPECT_EQ(written, Vector3d(0, -9.81, 0));
  EXPECT_EQ(xml.find("_z\""), std::string::npos);  // no z slide joints
}

TEST(ExportMjcf, InvalidModelIsRefused) {
  analysis::SpringNetwork n = braced_lattice(1, 1, 1, 0.05);
  n.springs[2].stiffness = -1;
  EXPECT_THROW(mjcf_document(n), nurbs::InputError);
}

#ifdef ISOSPRING_HAVE_MUJOCO
struct MujocoModel {
  mjModel* model = nullptr;
  mjData* data = nullptr;
  ~MujocoModel() {
    if (data) mj_deleteData(data);
    if (model) mj_deleteModel(model);
  }
};

TEST(ExportMjcf, MujocoSettlesToTheLinearSpringSolution) {
  const double h = 0.05;
  const analysis::SpringNetwork n = braced_lattice(3, 1, 1, h);
  // Loads on the free end: bending (-z), shear (+y) and a little tension (+x).
  std::vector<Vector3d> forces(n.positions.size(), Vector3d::Zero());
  for (size_t p = 0; p < n.positions.size(); ++p)
    if (std::abs(n.positions[p].x() - 3 * h) < 1e-12) forces[p] = Vector3d(1e-3, 5e-4, -1.5e-3);
  const std::vector<Vector3d> expected = linear_solution(n, forces);
  double largest = 0;
  for (const Vector3d& u : expected) largest = std::max(largest, u.norm());
  ASSERT_GT(largest, 0);
  ASSERT_LT(largest / h, 1e-3);  // small displacements: linear statics applies

  MjcfOptions options;
  options.gravity = Vector3d::Zero();
  options.comment = "test -- lattice";
  const fs::path dir = fs::temp_directory_path() /
                       (std::string("isospring_test_mjcf-") + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path path = dir / "lattice.xml";
  write_mjcf(path, n, options);

  char error[1000] = "";
  MujocoModel mj;
  mj.model = mj_loadXML(path.c_str(), nullptr, error, sizeof(error));
  ASSERT_NE(mj.model, nullptr) << error;
  mj.data = mj_makeData(mj.model);
  ASSERT_EQ(mj.model->ntendon, static_cast<int>(n.springs.size()));
  for (size_t s = 0; s < n.springs.size(); ++s) {
    EXPECT_EQ(mj.model->tendon_stiffness[s], n.springs[s].stiffness);
    EXPECT_EQ(mj.model->tendon_damping[s], n.springs[s].damping);
    EXPECT_EQ(mj.model->tendon_lengthspring[s], n.springs[s].rest_length);
  }

  // Generalized forces: each slide joint's dof takes its force component.
  std::vector<std::array<int, 3>> dof(n.positions.size(), {-1, -1, -1});
  for (size_t p = 0; p < n.positions.size(); ++p) {
    if (n.fixed[p]) continue;
    const int body = mj_name2id(mj.model, mjOBJ_BODY, ("particle_" + std::to_string(p)).c_str());
    ASSERT_GE(body, 0);
    EXPECT_DOUBLE_EQ(mj.model->body_mass[body], n.masses[p]);
    for (int c = 0; c < 3; ++c) {
      const std::string joint = "particle_" + std::to_string(p) + "_" + "xyz"[c];
      const int j = mj_name2id(mj.model, mjOBJ_JOINT, joint.c_str());
      ASSERT_GE(j, 0) << joint;
      dof[p][static_cast<size_t>(c)] = mj.model->jnt_dofadr[j];
      mj.data->qfrc_applied[mj.model->jnt_dofadr[j]] = forces[p](c);
    }
  }
  // Let it settle: the tendon damping removes the motion; stop when velocities vanish.
  double speed = 1;
  int steps = 0;
  for (; steps < 200000 && (steps < 100 || speed > 1e-9); ++steps) {
    mj_step(mj.model, mj.data);
    speed = 0;
    for (int v = 0; v < mj.model->nv; ++v) speed = std::max(speed, std::abs(mj.data->qvel[v]));
  }
  double worst = 0;
  for (size_t p = 0; p < n.positions.size(); ++p) {
    if (n.fixed[p]) continue;
    Vector3d u;
    for (int c = 0; c < 3; ++c)
      u(c) =
          mj.data->qpos[mj.model->jnt_qposadr[mj.model->dof_jntid[dof[p][static_cast<size_t>(c)]]]];
    worst = std::max(worst, (u - expected[p]).norm());
  }
  std::printf(
      "MuJoCo vs linear spring statics: max |du| / max |u| = %.2e after %d steps (dt %.2e)\n",
      worst / largest, steps, mj.model->opt.timestep);
  // The brief asks for 1%; with strains ~1e-4 the nonlinearity is ~1e-4, so 1e-3 is asserted.
  EXPECT_LT(worst / largest, 1e-3);
}
// The flat model under its default (in-plane) gravity, exported and simulated by MuJoCo: it
// moves, and settles on the linear spring statics of the weights m_i g (2D and 3D are both
// covered: MujocoSettlesToTheLinearSpringSolution is the 3D lattice).
TEST(ExportMjcf, MujocoMovesAFlatModelUnderItsDefaultGravity) {
  const double h = 0.05;
  analysis::SpringNetwork n = braced_lattice(3, 1, 0, h);
  n.dimension = 2;
  // Stiff enough for linear statics (largest displacement ~1e-4 of a cell) under 9.81 m/s^2.
  for (auto& spring : n.springs) spring.stiffness *= 1000.0, spring.damping *= 100.0;
  MjcfOptions options;
  options.gravity = engine_gravity(n, Vector3d::Zero(), std::nullopt);
  std::vector<Vector3d> weights(n.positions.size(), Vector3d::Zero());
  for (size_t p = 0; p < n.positions.size(); ++p) weights[p] = n.masses[p] * options.gravity;
  const std::vector<Vector3d> expected = linear_solution(n, weights);
  double largest = 0;
  for (const Vector3d& u : expected) largest = std::max(largest, u.norm());
  ASSERT_GT(largest, 0);
  ASSERT_LT(largest / h, 1e-3);

  const fs::path dir = fs::temp_directory_path() /
                       (std::string("isospring_test_mjcf2d-") + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path path = dir / "flat.xml";
  write_mjcf(path, n, options);
  char error[1000] = "";
  MujocoModel mj;
  mj.model = mj_loadXML(path.c_str(), nullptr, error, sizeof(error));
  ASSERT_NE(mj.model, nullptr) << error;
  mj.data = mj_makeData(mj.model);
  double speed = 1;
  int steps = 0;
  for (; steps < 400000 && (steps < 100 || speed > 1e-9); ++steps) {
    mj_step(mj.model, mj.data);
    speed = 0;
    for (int v = 0; v < mj.model->nv; ++v) speed = std::max(speed, std::abs(mj.data->qvel[v]));
  }
  double worst = 0;
  for (size_t p = 0; p < n.positions.size(); ++p) {
    if (n.fixed[p]) continue;
    Vector3d u = Vector3d::Zero();
    for (int c = 0; c < 2; ++c) {
      const std::string joint = "particle_" + std::to_string(p) + "_" + "xy"[c];
      const int j = mj_name2id(mj.model, mjOBJ_JOINT, joint.c_str());
      ASSERT_GE(j, 0) << joint;
      u(c) = mj.data->qpos[mj.model->jnt_qposadr[j]];
    }
    worst = std::max(worst, (u - expected[p]).norm());
  }
  std::printf("MuJoCo (flat model, gravity -y) vs linear spring statics: %.2e after %d steps\n",
              worst / largest, steps);
  EXPECT_LT(worst / largest, 1e-3);
  fs::remove_all(dir);
}
#else
TEST(ExportMjcf, MujocoSettlesToTheLinearSpringSolution) {
  GTEST_SKIP() << "MuJoCo (libmujoco-dev) not found at configure time; the simulation check of "
                  "the MJCF export is skipped";
}
#endif

}  // namespace
}  // namespace isospring::io
