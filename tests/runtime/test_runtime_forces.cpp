// The runtime (runtime.h) against the project's own mechanics: a model with every term kind is
// built on a thesis object's control net (fitting::build_spring_mesh: springs, cell volume and
// shear terms, strain points), written with io::write_model_json, loaded by the runtime and
// evaluated at a deformed, moving state. Its forces must be analysis' spring_forces +
// damping_forces to 1e-12 (relative to the largest force), and its Jacobian-vector products both
// analysis' exact tangent (tangent_stiffness, an independent derivation) and central finite
// differences of the runtime's own forces.
#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Sparse>
#include <filesystem>
#include <random>

#include "isospring/analysis/spring_mechanics.hpp"
#include "isospring/fitting/spring_mesh.hpp"
#include "isospring/fitting/thesis_experiments.hpp"
#include "isospring/io/model_file.hpp"
#include "isospring/runtime/runtime.h"
#include "runtime_test_support.hpp"

namespace isospring::runtime {
namespace {

using Eigen::VectorXd;

// The object's net with every term kind and random (positive) parameters, so that a mix-up of
// terms or indices would show.
analysis::SpringNetwork every_term_network(const fitting::ThesisObject& object, int points) {
  fitting::SpringMeshOptions options;
  options.volume_terms = true;
  options.shear_terms = true;
  options.strain_points = points;
  analysis::SpringNetwork n = fitting::build_spring_mesh(object.problem, options).network;
  std::mt19937 random(7);
  std::uniform_real_distribution<double> factor(0.5, 2.0);
  n.masses.assign(n.positions.size(), 0.0);
  n.fixed.assign(n.positions.size(), false);
  for (size_t p = 0; p < n.positions.size(); ++p) n.masses[p] = 0.1 * factor(random);
  n.fixed[0] = true;
  for (analysis::Spring& s : n.springs) {
    s.stiffness = 1e3 * factor(random);
    s.damping = 2.0 * factor(random);
  }
  for (analysis::VolumeTerm& t : n.volumes) t.modulus = 5e3 * factor(random);
  return n;
}

struct Fixture {
  analysis::SpringNetwork network;
  ModelHandle model;
  VectorXd x, v;  // deformed, moving state
};

Fixture load(const analysis::SpringNetwork& network, const std::string& name) {
  Fixture f;
  f.network = network;
  const std::filesystem::path path = test_directory() / (name + ".json");
  io::write_model_json(path, network);
  f.model = load_model(path);
  // Displacements of ~5% of the object's size and velocities: every term is well away from rest
  // (the nonlinear parts of the forces matter).
  std::mt19937 random(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  f.x = analysis::flat_positions(network);
  f.v = VectorXd(f.x.size());
  for (Eigen::Index e = 0; e < f.x.size(); ++e) {
    f.x[e] += 0.05 * unit(random);
    f.v[e] = unit(random);
  }
  return f;
}

VectorXd runtime_forces(const Fixture& f, bool damped, double* energy = nullptr) {
  VectorXd out(f.x.size());
  const double e =
      isospring_model_forces(f.model.get(), f.x.data(), damped ? f.v.data() : nullptr, out.data());
  if (energy) *energy = e;
  return out;
}

void expect_forces_match(const Fixture& f) {
  ASSERT_EQ(isospring_model_state_size(f.model.get()), static_cast<size_t>(f.x.size()));
  double energy = 0.0;
  const VectorXd ours = runtime_forces(f, true, &energy);
  const VectorXd theirs =
      analysis::spring_forces(f.network, f.x) + analysis::damping_forces(f.network, f.x, f.v);
  const double scale = theirs.cwiseAbs().maxCoeff();
  EXPECT_LE((ours - theirs).cwiseAbs().maxCoeff(), 1e-12 * scale) << "largest force " << scale;
  EXPECT_NEAR(energy, analysis::spring_energy(f.network, f.x),
              1e-12 * analysis::spring_energy(f.network, f.x));
  // Without velocities: elastic forces only.
  const VectorXd elastic = runtime_forces(f, false);
  EXPECT_LE((elastic - analysis::spring_forces(f.network, f.x)).cwiseAbs().maxCoeff(),
            1e-12 * scale);
}

void expect_jvp_matches(Fixture& f) {
  std::mt19937 random(3);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  VectorXd dx(f.x.size()), dv(f.x.size());
  for (Eigen::Index e = 0; e < dx.size(); ++e) {
    dx[e] = unit(random);
    dv[e] = unit(random);
  }
  // Elastic part: -K(x) dx with analysis' exact tangent.
  VectorXd df(f.x.size());
  isospring_model_force_jvp(f.model.get(), f.x.data(), nullptr, dx.data(), nullptr, df.data());
  const VectorXd tangent = -(analysis::tangent_stiffness(f.network, f.x) * dx);
  const double scale = tangent.cwiseAbs().maxCoeff();
  EXPECT_LE((df - tangent).cwiseAbs().maxCoeff(), 1e-12 * scale) << "largest " << scale;

  // Damped, along (dx, dv): central differences of the runtime's forces, step h. Their error is
  // h^2 f''' / 6 plus round-off eps |f| / h; h = 1e-5 of the unit direction keeps both near
  // 1e-9 of the largest entry, so 1e-7 relative is a tight bound that a wrong term would miss by
  // orders of magnitude.
  isospring_model_force_jvp(f.model.get(), f.x.data(), f.v.data(), dx.data(), dv.data(), df.data());
  const double h = 1e-5;
  Fixture plus = f, minus = f;
  plus.x += h * dx;
  plus.v += h * dv;
  minus.x -= h * dx;
  minus.v -= h * dv;
  const VectorXd central = (runtime_forces(plus, true) - runtime_forces(minus, true)) / (2 * h);
  const double central_scale = central.cwiseAbs().maxCoeff();
  EXPECT_LE((df - central).cwiseAbs().maxCoeff(), 1e-7 * central_scale)
      << "largest " << central_scale;
}

TEST(RuntimeForces, CubeWithEveryTermMatchesAnalysis) {
  Fixture f = load(every_term_network(fitting::thesis_cube(4), 2), "cube");
  for (int term : {ISOSPRING_TERM_SPRINGS, ISOSPRING_TERM_CELL_VOLUME, ISOSPRING_TERM_CELL_SHEAR,
                   ISOSPRING_TERM_POINT_VOLUME, ISOSPRING_TERM_POINT_SHEAR})
    EXPECT_GT(isospring_model_term_count(f.model.get(), term), 0u) << term;
  expect_forces_match(f);
  expect_jvp_matches(f);
}

TEST(RuntimeForces, SquareMembraneWithEveryTermMatchesAnalysis) {
  Fixture f = load(every_term_network(fitting::thesis_square(5), 3), "square");
  EXPECT_EQ(isospring_model_dimension(f.model.get()), 2);
  expect_forces_match(f);
  expect_jvp_matches(f);
}

// Curved patches with collapsed poles (cells of zero volume are left out, strain points keep
// their gradients), at the analysis' full Gauss rule.
TEST(RuntimeForces, CoupledSpheroidAtTheFullRuleMatchesAnalysis) {
  Fixture f = load(every_term_network(fitting::thesis_coupled_spheroid(), 3), "spheroid");
  EXPECT_EQ(isospring_model_term_count(f.model.get(), ISOSPRING_TERM_POINT_SHEAR), 864u);
  expect_forces_match(f);
  expect_jvp_matches(f);
}

// Masking: the sum over the kinds evaluated one at a time is the whole, and an engine that runs
// the springs itself gets the rest.
TEST(RuntimeForces, TermMasksSplitTheForces) {
  Fixture f = load(every_term_network(fitting::thesis_cube(3), 1), "cube_masks");
  const VectorXd whole = runtime_forces(f, true);
  VectorXd sum = VectorXd::Zero(whole.size());
  for (int term : {ISOSPRING_TERM_SPRINGS, ISOSPRING_TERM_CELL_VOLUME, ISOSPRING_TERM_CELL_SHEAR,
                   ISOSPRING_TERM_POINT_VOLUME, ISOSPRING_TERM_POINT_SHEAR}) {
    isospring_model_set_terms(f.model.get(), term);
    const VectorXd part = runtime_forces(f, true);
    EXPECT_GT(part.norm(), 0.0) << term;
    sum += part;
  }
  EXPECT_LE((sum - whole).cwiseAbs().maxCoeff(), 1e-12 * whole.cwiseAbs().maxCoeff());
  isospring_model_set_terms(f.model.get(), ISOSPRING_TERM_ALL & ~ISOSPRING_TERM_SPRINGS);
  analysis::SpringNetwork no_springs = f.network;
  no_springs.springs.clear();
  EXPECT_LE(
      (runtime_forces(f, true) - analysis::spring_forces(no_springs, f.x)).cwiseAbs().maxCoeff(),
      1e-12 * whole.cwiseAbs().maxCoeff());
}

// One call per step allocates nothing: operator new is counted around the calls.
TEST(RuntimeForces, StepCallsDoNotAllocate) {
  Fixture f = load(every_term_network(fitting::thesis_cube(3), 2), "cube_alloc");
  VectorXd out(f.x.size()), dx = VectorXd::Ones(f.x.size());
  const long before = allocation_count();
  for (int step = 0; step < 3; ++step) {
    isospring_model_forces(f.model.get(), f.x.data(), f.v.data(), out.data());
    isospring_model_force_jvp(f.model.get(), f.x.data(), f.v.data(), dx.data(), dx.data(),
                              out.data());
  }
  EXPECT_EQ(allocation_count(), before);
}

}  // namespace
}  // namespace isospring::runtime
