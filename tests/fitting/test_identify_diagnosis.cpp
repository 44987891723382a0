// The residual description: exact on fields built from its own modes, noise-level on pure noise,
// and, inside the loop, a hidden rigid motion of the measuring frame shows up as constant and
// linear residual energy while a pure-noise residual does not.
#include <gtest/gtest.h>

#include <random>

#include "isospring/fitting/identify.hpp"
#include "isospring/fitting/identify_diagnosis.hpp"
#include "test_identify_plate.hpp"

namespace isospring::fitting {
namespace {

struct Grid {
  std::vector<Eigen::Vector3d> positions;
  std::vector<int> group;
};

Grid grid(int cases) {
  Grid g;
  for (int l = 0; l < cases; ++l)
    for (int j = 0; j < 6; ++j)
      for (int i = 0; i < 12; ++i) {
        g.positions.emplace_back(0.1 * (i + 0.5) / 12, 0.04 * (j + 0.5) / 6, 0.0);
        g.group.push_back(l);
      }
  return g;
}

TEST(ResidualDescription, ConstantAndLinearFieldsAreFullyExplained) {
  const Grid g = grid(3);
  std::vector<Eigen::Vector3d> r;
  for (size_t m = 0; m < g.positions.size(); ++m) {
    const Eigen::Vector3d& x = g.positions[m];
    const double l = g.group[m] + 1.0;
    r.emplace_back(2e-6 * l, -1e-6 + 3e-5 * l * (x.x() - 0.05), 0.0);  // translation, rotation
  }
  const std::vector<Eigen::VectorXd> loads{Eigen::VectorXd::Constant(4, 1.0),
                                           Eigen::VectorXd::Constant(4, 2.0),
                                           Eigen::VectorXd::Constant(4, 3.0)};
  const ResidualDescription d = describe_residual(g.positions, r, g.group, {"a", "b", "c"}, loads,
                                                  2, Eigen::Vector3d(0.05, 0.02, 0), 0.1);
  // Projections onto the modes reproduce the field to rounding.
  EXPECT_NEAR(d.constant_fraction + d.linear_fraction, 1.0, 1e-12);
  EXPECT_GT(d.linear_fraction, 0.05);
  // 3 modes per component, 72 markers per case: noise would put 3/72 of its energy there.
  EXPECT_DOUBLE_EQ(d.noise_fraction, 3.0 / 72.0);
  // Per case: the x residual is 2e-6 * l exactly; the rms grows with the load norm 2 * l.
  ASSERT_EQ(d.load_cases.size(), 3u);
  for (int l = 0; l < 3; ++l) {
    EXPECT_NEAR(d.load_cases[l].component_rms.x(), 2e-6 * (l + 1), 1e-18);
    EXPECT_NEAR(d.load_cases[l].load_norm, 2.0 * (l + 1), 1e-15);
    EXPECT_NEAR(d.load_cases[l].resultant.x(), 2.0 * (l + 1), 1e-15);  // 2 nodes x (l + 1)
  }
  EXPECT_GT(d.load_correlation, 0.99);
}

TEST(ResidualDescription, PureNoiseStaysAtTheNoiseShare) {
  const Grid g = grid(2);
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 1e-6);
  std::vector<Eigen::Vector3d> r;
  for (size_t m = 0; m < g.positions.size(); ++m) r.emplace_back(noise(rng), noise(rng), 0.0);
  const std::vector<Eigen::VectorXd> loads{Eigen::VectorXd::Ones(4), Eigen::VectorXd::Ones(4)};
  const ResidualDescription d = describe_residual(g.positions, r, g.group, {"a", "b"}, loads, 2,
                                                  Eigen::Vector3d(0.05, 0.02, 0), 0.1);
  // The explained share is chi^2_12 / chi^2_288: mean 12/288 = 4.2%, standard deviation ~1.7%;
  // 12% is more than 4 standard deviations above the mean.
  EXPECT_LT(d.constant_fraction + d.linear_fraction, 0.12);
  EXPECT_NEAR(d.rms, 1e-6, 0.15e-6);
  EXPECT_TRUE(std::isnan(d.load_correlation));  // two load cases: no correlation
}

IdentifyResult identify_with(const std::vector<std::pair<std::string, Eigen::VectorXd>>& hidden) {
  const analysis::Problem prior = testing::plate_problem();
  std::vector<Marker> markers = testing::grid_markers(prior);
  const auto placements = place_markers(prior.patches, markers, 1e-9).placements;
  analysis::Problem truth = prior;
  truth.material.youngs_modulus *= 1.15;
  testing::add_noise(markers, simulate_markers(truth, markers, placements, hidden), 1e-6, 4);
  IdentifyOptions options;
  // Data simulated on this very discretisation: it has no discretisation error to control.
  options.discretization.enabled = false;
  options.holdout = false;
  return identify(prior, markers, placements, options);
}

TEST(ResidualDescription, RigidOffsetIsConstantAndLinearInTheLoop) {
  const Eigen::VectorXd offset =
      (Eigen::VectorXd(6) << 3e-6, -2e-6, 4e-5, -1e-6, 3e-6, -2e-5).finished();
  const IdentifyResult r = identify_with({{"rigid_offset_per_load", offset}});
  const ResidualDescription& before = r.residual_before;
  // The baseline residual is the rigid motion (rms ~3e-6 m) plus 1e-6 m noise: about 90% of its
  // energy is in the modes (noise share ~4%); most of it, by a wide margin.
  EXPECT_GT(before.constant_fraction + before.linear_fraction, 0.8) << before.summary;
  // After the offset is fitted, the residual is noise: it falls back to the noise share (the
  // fitted offset removed exactly these modes, so the share is below it).
  const ResidualDescription& after = r.residual_after;
  EXPECT_LT(after.constant_fraction + after.linear_fraction, 0.12) << after.summary;
  ASSERT_FALSE(r.rounds.empty());
  EXPECT_NEAR(r.rounds[0].residual.rms, before.rms, 1e-3 * before.rms);
}

TEST(ResidualDescription, PureNoiseIsNotSmoothInTheLoop) {
  const IdentifyResult r = identify_with({});
  EXPECT_TRUE(r.effects_added.empty());
  const ResidualDescription& before = r.residual_before;
  EXPECT_LT(before.constant_fraction + before.linear_fraction, 0.12) << before.summary;
  EXPECT_NE(before.summary.find("no more than noise"), std::string::npos) << before.summary;
}

}  // namespace
}  // namespace isospring::fitting
