// Standard errors of the identification: the column-scaled Gauss-Newton covariance against a
// direct inverse, and a 3D loop (box bar, hidden rigid motion of the measuring frame) whose
// parameters mix scales of 1 (E ratio) and 1e-5 (rotations). Before the column scaling every
// standard error in 3D came out NaN ("near rank deficient").
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "isospring/fitting/identify.hpp"
#include "isospring/nurbs/refine.hpp"

namespace isospring::fitting {
namespace {

TEST(IdentifyCovariance, ColumnScalingMatchesTheDirectInverse) {
  // J = A S with A well conditioned and S spanning 11 orders of magnitude: (J^T J)^-1 =
  // S^-1 (A^T A)^-1 S^-1, where (A^T A)^-1 is computed directly without trouble.
  std::mt19937 rng(3);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::MatrixXd a(60, 4);
  for (Eigen::Index i = 0; i < a.size(); ++i) a.data()[i] = normal(rng);
  const Eigen::Vector4d s(1e6, 1.0, 1e-5, 3e2);
  const Eigen::MatrixXd expected =
      s.cwiseInverse().asDiagonal() * (a.transpose() * a).inverse() * s.cwiseInverse().asDiagonal();
  const Eigen::MatrixXd covariance = gauss_newton_covariance(a * s.asDiagonal());
  // Both sides are exact up to rounding in a problem of condition ~10 after scaling.
  for (Eigen::Index i = 0; i < 4; ++i)
    for (Eigen::Index j = 0; j < 4; ++j)
      EXPECT_NEAR(covariance(i, j), expected(i, j),
                  1e-10 * std::sqrt(expected(i, i) * expected(j, j)))
          << i << "," << j;
}

TEST(IdentifyCovariance, CollinearParametersAreNaNOthersFinite) {
  Eigen::MatrixXd j(5, 3);
  j << 1, 2, 0.3, 2, 4, -1, 3, 6, 0.5, 4, 8, 2, 5, 10, 1;  // column 1 = 2 x column 0
  const Eigen::MatrixXd covariance = gauss_newton_covariance(j);
  EXPECT_TRUE(std::isnan(covariance(0, 0)));
  EXPECT_TRUE(std::isnan(covariance(1, 1)));
  // Column 2 is orthogonal to the null direction (2, -1, 0) / sqrt(5): its variance is that of
  // the pseudo-inverse, equal to the variance with column 1 dropped.
  Eigen::MatrixXd reduced(5, 2);
  reduced << j.col(0), j.col(2);
  const double expected = (reduced.transpose() * reduced).inverse()(1, 1);
  EXPECT_NEAR(covariance(2, 2), expected, 1e-12 * expected);
}

constexpr double kLength = 0.2, kSection = 0.04;
constexpr double kSigma = 1e-7;  // noise [m]; displacements are ~1e-5 m

// A clamped polymer bar (E 1 GPa), degree 2, 4 x 2 x 2 elements; tension and two bendings.
analysis::Problem bar_problem() {
  const nurbs::KnotVector linear(1, {0, 0, 1, 1});
  std::vector<Eigen::Vector3d> points;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) points.emplace_back(kLength * i, kSection * j, kSection * k);
  analysis::Problem problem;
  problem.formulation = analysis::Formulation::kSolid;
  problem.material = {1e9, 0.3, 7800, 1.0};
  problem.patches.push_back(
      nurbs::k_refine(nurbs::Patch({linear, linear, linear}, points), {2, 2, 2}, {4, 2, 2}));
  analysis::Support clamp;
  clamp.side = {0, 0, 0};
  clamp.fixed = {true, true, true};
  problem.supports.push_back(clamp);
  const std::vector<std::pair<std::string, Eigen::Vector3d>> loads{
      {"tension", {2e5, 0, 0}}, {"bend_y", {0, 2e4, 0}}, {"bend_z", {0, 0, 2e4}}};
  for (const auto& [id, traction] : loads) {
    analysis::LoadCase load;
    load.id = id;
    load.tractions.push_back({{0, 0, 1}, traction, {}});
    problem.load_cases.push_back(load);
  }
  return problem;
}

TEST(Identify3D, RigidOffsetWithFiniteStandardErrors) {
  const analysis::Problem prior = bar_problem();
  std::vector<Marker> markers;  // 6 x 3 x 3 per load case inside the bar: 162 markers
  int row = 2;
  for (const auto& load : prior.load_cases)
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 6; ++i) {
          Marker m;
          m.load_case = load.id;
          m.position = {kLength * (i + 0.5) / 6, kSection * (j + 0.5) / 3,
                        kSection * (k + 0.5) / 3};
          m.row = row++;
          markers.push_back(m);
        }
  const auto placements = place_markers(prior.patches, markers, 1e-9).placements;
  analysis::Problem truth = prior;
  truth.material.youngs_modulus *= 1.1;
  Eigen::VectorXd rigid(18);  // per load case: translations [m], rotations [rad]
  for (int l = 0; l < 3; ++l)
    rigid.segment(6 * l, 6) << 2e-6 * (l + 1), -1e-6, 1.5e-6, 1e-5, -2e-5 * (l + 1), 1e-5;
  const auto clean =
      simulate_markers(truth, markers, placements, {{"rigid_offset_per_load", rigid}});
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, kSigma);
  for (size_t m = 0; m < markers.size(); ++m)
    for (int c = 0; c < 3; ++c) markers[m].displacement[c] = clean[m][c] + noise(rng);

  IdentifyOptions options;
  // Data simulated on this very discretisation: it has no discretisation error to control.
  options.discretization.enabled = false;
  options.holdout = false;
  options.noise_sigma = kSigma;
  const IdentifyResult r = identify(prior, markers, placements, options);
  ASSERT_EQ(r.effects_added, std::vector<std::string>{"rigid_offset_per_load"});
  ASSERT_EQ(r.parameters.size(), 19u);
  // Every estimate has a finite positive standard error and lies within 3.5 of them of the
  // truth (19 parameters: P(max |z| > 3.5) ~ 0.9%); the E error is the dominant one.
  for (size_t k = 0; k < r.parameters.size(); ++k) {
    const ParameterEstimate& p = r.parameters[k];
    const double expected = k == 0 ? 1.1e9 : rigid[static_cast<Eigen::Index>(k - 1)];
    ASSERT_TRUE(std::isfinite(p.standard_error)) << p.name;
    EXPECT_GT(p.standard_error, 0.0) << p.name;
    EXPECT_LT(std::abs(p.value - expected), 3.5 * p.standard_error)
        << p.name << " = " << p.value << " +- " << p.standard_error << ", truth " << expected;
  }
  // The E standard error is small against E (a strong, well-posed fit): < 0.1% here.
  EXPECT_LT(r.parameters[0].standard_error, 1e-3 * 1.1e9);
  // The residual is the noise: rms within 20% of sigma (486 components, relative spread ~3%).
  EXPECT_LT(r.after.rms, 1.2 * kSigma);
  EXPECT_GT(r.after.rms, 0.8 * kSigma);
}

}  // namespace
}  // namespace isospring::fitting
