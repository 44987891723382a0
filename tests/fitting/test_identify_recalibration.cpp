// Carrying an identification through to the spring model: the recalibrated NMSM, solved with its
// exported loads (particle forces plus m_i g), reproduces an independent IGA solve of the
// corrected problem (identified E, identified gravity in every load case) with the reported
// %e_rms; without the gravity forces it does not.
#include <gtest/gtest.h>

#include "isospring/analysis/spring_static.hpp"
#include "isospring/analysis/static_solver.hpp"
#include "isospring/fitting/identify_recalibration.hpp"
#include "test_identify_plate.hpp"

namespace isospring::fitting {
namespace {

struct Identified {
  analysis::Problem prior;
  IdentifyResult result;
};

Identified identify_plate(const std::vector<std::pair<std::string, Eigen::VectorXd>>& hidden) {
  Identified out;
  out.prior = testing::plate_problem();
  std::vector<Marker> markers = testing::grid_markers(out.prior);
  const auto placements = place_markers(out.prior.patches, markers, 1e-9).placements;
  analysis::Problem truth = out.prior;
  truth.material.youngs_modulus *= 1.15;
  testing::add_noise(markers, simulate_markers(truth, markers, placements, hidden), 1e-6, 2);
  IdentifyOptions options;
  // Data simulated on this very discretisation: it has no discretisation error to control.
  options.discretization.enabled = false;
  options.holdout = false;
  out.result = identify(out.prior, markers, placements, options);
  return out;
}

std::vector<Eigen::Vector3d> points(const Eigen::VectorXd& flat, int dim) {
  std::vector<Eigen::Vector3d> p(static_cast<size_t>(flat.size() / dim), Eigen::Vector3d::Zero());
  for (size_t a = 0; a < p.size(); ++a)
    p[a].head(dim) = flat.segment(static_cast<Eigen::Index>(a) * dim, dim);
  return p;
}

TEST(IdentifyRecalibration, GravityIsCarriedAsParticleForces) {
  const Identified id = identify_plate({{"gravity", Eigen::Vector2d(0.0, -9.81)}});
  ASSERT_EQ(id.result.effects_added, std::vector<std::string>{"gravity"});
  const Recalibration rc = recalibrate_identified(id.prior, id.result);

  // Independent corrected reference: the static solver on the prior with the identified E and
  // the identified g added to every load case.
  analysis::Problem corrected = id.prior;
  corrected.material.youngs_modulus = id.result.youngs_modulus;
  const Eigen::VectorXd& g = id.result.effect_values[0].second;
  for (auto& load : corrected.load_cases) load.gravity.head(2) = g;
  const analysis::StaticResult reference = analysis::solve_static(corrected);
  EXPECT_NEAR(rc.gravity.y(), g[1], 1e-15);

  const analysis::SpringNetwork& network = rc.calibration.mesh.network;
  const int dim = 2;
  // One patch, no merging: particle p carries node p.
  ASSERT_EQ(network.positions.size() * dim,
            static_cast<size_t>(reference.load_cases[0].displacement.size()));
  double sum = 0.0;
  for (size_t l = 0; l < corrected.load_cases.size(); ++l) {
    const Eigen::VectorXd& u_ref = reference.load_cases[l].displacement;
    // The identification's corrected reference is the same model: agreement to rounding.
    EXPECT_LT((id.result.corrected_displacements[l] - u_ref).norm(), 1e-9 * u_ref.norm()) << l;
    Eigen::VectorXd gravity_force = Eigen::VectorXd::Zero(u_ref.size());
    for (size_t p = 0; p < network.positions.size(); ++p)
      gravity_force.segment(static_cast<Eigen::Index>(p) * dim, dim) =
          network.masses[p] * rc.gravity.head(dim);
    const Eigen::VectorXd with =
        analysis::solve_spring_linear(network, rc.particle_loads[l] + gravity_force).displacement;
    const Eigen::VectorXd without =
        analysis::solve_spring_linear(network, rc.particle_loads[l]).displacement;
    const double e_with = error_metrics(points(u_ref, dim), points(with, dim)).percent_e_rms;
    const double e_without = error_metrics(points(u_ref, dim), points(without, dim)).percent_e_rms;
    // With m_i g the spring model sees exactly the loads it was fitted under (row-sum lumped
    // masses give the consistent self-weight), so its error is the reported one to rounding.
    EXPECT_NEAR(e_with, rc.calibration.fit[l].control.percent_e_rms, 1e-6 * e_with) << l;
    // Without them the self-weight deflection (comparable to the load's own here) is missing.
    EXPECT_GT(e_without, 5.0 * e_with) << l;
    sum += e_with * e_with;
  }
  EXPECT_NEAR(rc.percent_e_rms, std::sqrt(sum / 2.0), 1e-6 * rc.percent_e_rms);
  EXPECT_NEAR(rc.corrected.material.youngs_modulus, id.result.youngs_modulus, 0.0);
}

TEST(IdentifyRecalibration, LoadScaleScalesTheLoadsAndRigidOffsetIsLeftOut) {
  const Eigen::VectorXd offset = Eigen::Vector3d(3e-6, -2e-6, 4e-5);  // the frame's, shared
  const Identified id = identify_plate(
      {{"load_scale", Eigen::VectorXd::Constant(1, 0.05)}, {"rigid_offset", offset}});
  ASSERT_EQ(id.result.effects_added.size(), 2u);
  const Recalibration rc = recalibrate_identified(id.prior, id.result);
  ASSERT_EQ(rc.load_factors.size(), 2u);
  EXPECT_EQ(rc.load_factors[0], 1.0);
  double s = 0.0;
  for (const auto& [name, values] : id.result.effect_values)
    if (name == "load_scale") s = values[0];
  EXPECT_NEAR(rc.load_factors[1], 1.0 + s, 1e-15);
  // The second case's particle load is the nominal one times the factor (a traction).
  const Recalibration nominal = recalibrate_identified(id.prior, identify_plate({}).result);
  EXPECT_LT((rc.particle_loads[1] - rc.load_factors[1] * nominal.particle_loads[1]).norm(),
            1e-12 * rc.particle_loads[1].norm());
  EXPECT_TRUE(rc.gravity.isZero());
  // rigid_offset moves the markers only: the corrected reference is the static solve of the
  // corrected problem (identified E, scaled loads).
  const analysis::StaticResult reference = analysis::solve_static(rc.corrected);
  for (size_t l = 0; l < 2; ++l)
    EXPECT_LT((id.result.corrected_displacements[l] - reference.load_cases[l].displacement).norm(),
              1e-9 * reference.load_cases[l].displacement.norm());
}

// identify's "carrying over to the spring model" notes are the recalibration's, word for word:
// one carry-over (EffectType::carry_over) writes both, so the report cannot promise what the
// recalibration does not do. Here: load_scale carried, rigid_offset not.
TEST(IdentifyRecalibration, IdentifyNotesAreWhatTheRecalibrationDid) {
  const Identified id = identify_plate({{"load_scale", Eigen::VectorXd::Constant(1, 0.05)},
                                        {"rigid_offset", Eigen::Vector3d(3e-6, -2e-6, 4e-5)}});
  ASSERT_EQ(id.result.spring_model_notes.size(), 2u);
  const Recalibration rc = recalibrate_identified(id.prior, id.result);
  ASSERT_GE(rc.notes.size(), id.result.spring_model_notes.size());
  for (size_t k = 0; k < id.result.spring_model_notes.size(); ++k)
    EXPECT_EQ(rc.notes[k], id.result.spring_model_notes[k]);
  for (const auto& note : id.result.spring_model_notes) {
    if (note.rfind("load_scale: ", 0) == 0) {
      EXPECT_NE(note.find("load_scale: carried as scaled loads"), std::string::npos) << note;
      EXPECT_NE(rc.load_factors[1], 1.0);
    } else {
      EXPECT_NE(note.find("rigid_offset: NOT carried"), std::string::npos) << note;
    }
  }
}

}  // namespace
}  // namespace isospring::fitting

namespace isospring::fitting {
namespace {

// A grouped fit that cannot converge within its iterations at the requested grouping degrades
// to coarser groupings and says so; when every grouping fails, the error says what to change.
// Measured on this plate: in 20 Levenberg-Marquardt iterations gamma 0.001 and 0.01 do not
// converge, 0.1 does; in 2 iterations none does; in 200 the requested one does.
TEST(IdentifyRecalibration, NonConvergenceFallsBackToCoarserGroupings) {
  const Identified id = identify_plate({{"gravity", Eigen::Vector2d(0.0, -9.81)}});
  CalibrationSettings settings;
  settings.gamma = 0.001;  // one group per distinct rest length: many stiffnesses
  settings.max_iterations = 20;
  const Recalibration coarser = recalibrate_identified(id.prior, id.result, settings);
  EXPECT_DOUBLE_EQ(coarser.calibration.gamma, 0.1);
  bool said = false;
  for (const auto& n : coarser.notes)
    said = said || (n.find("coarser grouping gamma 0.1") != std::string::npos &&
                    n.find("did not converge with gamma 0.01") != std::string::npos);
  EXPECT_TRUE(said);

  settings.max_iterations = 2;
  try {
    recalibrate_identified(id.prior, id.result, settings);
    FAIL() << "expected the last grouping's failure";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("did not converge"), std::string::npos) << e.what();
  }

  settings.max_iterations = 200;
  const Recalibration requested = recalibrate_identified(id.prior, id.result, settings);
  EXPECT_DOUBLE_EQ(requested.calibration.gamma, 0.001);
  for (const auto& n : requested.notes)
    EXPECT_EQ(n.find("coarser grouping"), std::string::npos) << n;
}

}  // namespace
}  // namespace isospring::fitting
