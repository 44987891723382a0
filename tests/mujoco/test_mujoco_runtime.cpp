// MuJoCo runs a calibrated model WITH every term: the [S15] cube calibrated with a volume and a
// shear term per net cell, and the coupled spheroid with strain points at the analysis' full
// Gauss rule (3 per direction) and a volume term per net cell, are exported (io::write_mjcf: the
// springs as tendons, the other terms in the model.json beside the scene), loaded by MuJoCo,
// the runtime attached as its passive-force callback (examples/mujoco/isospring_mujoco.c), and
// let settle under each held-out load case. The settled displacements must have the model's own
// calibrated %e_rms against the IGA reference.
//
// Why the tolerance: the calibration, its reference and its %e_rms are linear (scale-invariant);
// MuJoCo's springs and the terms are the exact nonlinear forces. The held-out load is therefore
// scaled so that the largest displacement is 1e-5 of the object's size, where the geometric
// nonlinearity changes the response by ~1e-5 relative (0.001 %e), and the dynamics run until
// the displacements change by less than 1e-8 of their largest per 500 steps (a 1e-6 relative
// residual at the slowest mode's decay rate). The difference to the model's linear static
// response is asserted below 0.01 % of o_max, so the engine's %e_rms is the calibrated one to
// +-0.01 (triangle inequality).
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>

#include "isospring/analysis/modal.hpp"
#include "isospring/analysis/spring_mechanics.hpp"
#include "isospring/analysis/spring_static.hpp"
#include "isospring/fitting/calibration.hpp"
#include "isospring/fitting/thesis_experiments.hpp"
#include "isospring/io/export_mjcf.hpp"
#include "isospring_mujoco.h"

namespace isospring {
namespace {

namespace fs = std::filesystem;
using Eigen::VectorXd;

struct Scene {
  mjModel* model = nullptr;
  mjData* data = nullptr;
  ~Scene() {
    isospring_mujoco_detach();
    if (data) mj_deleteData(data);
    if (model) mj_deleteModel(model);
  }
};

// Lowest natural frequency of the supported network [rad/s].
double lowest_omega(const analysis::SpringNetwork& network) {
  const int n = static_cast<int>(network.positions.size()) * network.dimension;
  const analysis::FreeDofSet dofs(n, analysis::fixed_dofs(network));
  const Eigen::SparseMatrix<double> k = dofs.restrict(analysis::rest_stiffness(network));
  const VectorXd m = dofs.restrict(analysis::mass_diagonal(network));
  Eigen::SparseMatrix<double> mass(m.size(), m.size());
  for (Eigen::Index d = 0; d < m.size(); ++d) mass.insert(d, d) = m[d];
  return std::sqrt(analysis::lowest_generalized_modes(k, mass, 1, 1e-8).eigenvalues[0]);
}

struct Settled {
  VectorXd u;  // particle displacements, flat
  long steps = 0;
  double us_per_step = 0.0;
};

// The scene under constant particle forces (flat), stepped until it stops moving.
Settled settle(const fs::path& xml, const analysis::SpringNetwork& network, const VectorXd& load) {
  Scene scene;
  char error[1000] = "";
  scene.model = mj_loadXML(xml.c_str(), nullptr, error, sizeof(error));
  EXPECT_NE(scene.model, nullptr) << error;
  if (!scene.model) return {};
  scene.data = mj_makeData(scene.model);
  EXPECT_EQ(isospring_mujoco_attach(scene.model, xml.c_str(), error, sizeof(error)), 1) << error;
  const int dim = network.dimension;
  for (size_t p = 0; p < network.positions.size(); ++p) {
    if (network.fixed[p]) continue;
    for (int c = 0; c < dim; ++c) {
      const std::string name = "particle_" + std::to_string(p) + "_" + "xyz"[c];
      const int joint = mj_name2id(scene.model, mjOBJ_JOINT, name.c_str());
      EXPECT_GE(joint, 0) << name;
      scene.data->qfrc_applied[scene.model->jnt_dofadr[joint]] =
          load[static_cast<Eigen::Index>(p) * dim + c];
    }
  }
  Settled out;
  out.u = VectorXd::Zero(static_cast<Eigen::Index>(network.positions.size()) * dim);
  VectorXd previous = out.u;
  const auto start = std::chrono::steady_clock::now();
  const long chunk = 500, limit = 400000;
  while (out.steps < limit) {
    for (long s = 0; s < chunk; ++s) mj_step(scene.model, scene.data);
    out.steps += chunk;
    EXPECT_EQ(isospring_mujoco_displacements(scene.data, out.u.data(), out.u.size()),
              network.positions.size());
    const double largest = out.u.cwiseAbs().maxCoeff();
    if (!std::isfinite(largest)) break;
    if ((out.u - previous).cwiseAbs().maxCoeff() < 1e-8 * largest) break;
    previous = out.u;
  }
  out.us_per_step =
      1e6 * std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() /
      static_cast<double>(out.steps);
  EXPECT_LT(out.steps, limit) << "MuJoCo did not settle";
  return out;
}

std::vector<Eigen::Vector3d> per_node(const VectorXd& u, const std::vector<int>& particle_of_node,
                                      int dim) {
  std::vector<Eigen::Vector3d> nodes;
  for (int p : particle_of_node) {
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    x.head(dim) = u.segment(static_cast<Eigen::Index>(p) * dim, dim);
    nodes.push_back(x);
  }
  return nodes;
}

// Calibrates `object` with `settings`, exports it, and checks every held-out case in MuJoCo.
void expect_mujoco_reproduces(const fitting::ThesisObject& object,
                              fitting::CalibrationSettings settings, const std::string& name) {
  settings.holdout_cases = object.holdout_cases;
  settings.field_metrics = false;
  const fitting::CalibrationResult calibration = fitting::calibrate(object.problem, settings);
  const analysis::SpringNetwork& network = calibration.mesh.network;
  ASSERT_FALSE(network.volumes.empty());
  const std::vector<int> particle_of_node =
      fitting::particle_of_node(object.problem, calibration.mesh);
  const int dim = network.dimension;

  io::MjcfOptions options;
  options.gravity = Eigen::Vector3d::Zero();  // the particle loads hold any self-weight
  options.particle_damping_rate = 2.0 * lowest_omega(network);  // the slowest mode critical
  // MuJoCo 2.2's Euler integrator takes joint damping implicitly; its "implicit" one also forms
  // dense nv x nv damping derivatives per tendon (~8-16 ms per step here), which a static
  // settle does not need.
  options.implicit_integrator = false;
  const fs::path dir =
      fs::temp_directory_path() / ("isospring_test_mujoco-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path xml = dir / (name + ".xml");
  io::write_mjcf(xml, network, options);
  ASSERT_TRUE(fs::exists(dir / (name + ".isospring.json")));

  Eigen::Vector3d low = network.positions[0], high = low;
  for (const Eigen::Vector3d& x : network.positions) {
    low = low.cwiseMin(x);
    high = high.cwiseMax(x);
  }
  for (const fitting::CaseErrors& held : calibration.holdout) {
    const auto at = std::find(calibration.load_ids.begin(), calibration.load_ids.end(), held.id);
    ASSERT_NE(at, calibration.load_ids.end()) << held.id;
    const VectorXd& load =
        calibration.particle_loads[static_cast<size_t>(at - calibration.load_ids.begin())];
    const VectorXd linear = analysis::solve_spring_linear(network, load).displacement;
    const double scale = 1e-5 * (high - low).norm() / linear.cwiseAbs().maxCoeff();
    // The IGA reference per node, from the calibration's own error: u_ref = u_model - error.
    std::vector<Eigen::Vector3d> reference = per_node(scale * linear, particle_of_node, dim);
    for (size_t a = 0; a < reference.size(); ++a) reference[a] -= scale * held.node_error[a];

    const Settled settled = settle(xml, network, scale * load);
    const fitting::ErrorMetrics engine =
        fitting::error_metrics(reference, per_node(settled.u, particle_of_node, dim));
    const fitting::ErrorMetrics to_linear =
        fitting::error_metrics(per_node(scale * linear, particle_of_node, dim),
                               per_node(settled.u, particle_of_node, dim));
    const double engine_to_model = to_linear.percent_e_rms * to_linear.o_max / engine.o_max;
    std::printf(
        "%s %s: calibrated %%e_rms %.4f, MuJoCo %.4f (MuJoCo vs the model's linear response "
        "%.2e %% of o_max; %ld steps of %.3g s, %.1f us per step with %zu tendons and %zu terms)\n",
        name.c_str(), held.id.c_str(), held.control.percent_e_rms, engine.percent_e_rms,
        engine_to_model, settled.steps, io::suggested_timestep(network), settled.us_per_step,
        network.springs.size(), network.volumes.size());
    EXPECT_LT(engine_to_model, 0.01) << held.id;
    EXPECT_LE(engine.percent_e_rms, held.control.percent_e_rms + 0.01) << held.id;
    EXPECT_NEAR(engine.percent_e_rms, held.control.percent_e_rms, 0.01) << held.id;
  }
}

TEST(MujocoRuntime, CubeWithVolumeAndShearTermsSettlesWithinItsCalibratedError) {
  fitting::CalibrationSettings settings;
  settings.mesh.volume_terms = true;
  settings.mesh.shear_terms = true;
  settings.fit_cases = {"fit_points", "fit"};
  settings.gamma = 0.5;
  expect_mujoco_reproduces(fitting::thesis_cube(), settings, "cube");
}

// The spheroid at [S15]'s net (2 x 9x5x3) with the strain points of the analysis' full rule:
// 864 points of 27 particles each, as the generalisation table's chosen model.
TEST(MujocoRuntime, SpheroidWithFullRuleStrainPointsSettlesWithinItsCalibratedError) {
  fitting::CalibrationSettings settings;
  settings.mesh.volume_terms = true;
  settings.mesh.strain_points = 3;
  settings.fit_cases = {"fit_points"};
  settings.gamma = 0.1;
  expect_mujoco_reproduces(fitting::thesis_coupled_spheroid(), settings, "spheroid");
}

}  // namespace
}  // namespace isospring
