// The large-deformation candidate's score test in later rounds of the loop starts Newton from an
// earlier round's solution and takes chord steps on an earlier round's tangent (the loop's
// FactorizationCache). Its result must be the one of a score test that reuses nothing: the same
// F, p and one-step estimate of w, round after round, as effects are added between them.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "../../fitting/src/identify/loop_state.hpp"
#include "isospring/fitting/effect.hpp"
#include "isospring/fitting/identify.hpp"
#include "test_identify_cantilever.hpp"

namespace isospring::fitting {
namespace {

using identify_loop::Fit;
using identify_loop::FitStart;
using identify_loop::Model;
using identify_loop::ScoreTest;

analysis::Problem cantilever(double q) {
  return testing::two_load_cantilever(q);
}
using testing::beam_markers;

void expect_relative(double reused, double fresh, double tolerance, const std::string& what) {
  EXPECT_LE(std::abs(reused - fresh), tolerance * std::abs(fresh))
      << what << ": " << reused << " with reuse, " << fresh << " without";
}

// Data of SVK (w = 1) with E = 1.15 E_prior, the second load case 20 % larger than declared and
// the measuring frame moved, noise 1/1000 of the tip deflection. The loop's steps by hand: the
// current fit, the candidate's score test on the loop's shared cache (what earlier rounds left
// there), and the same score test on a cache of its own (Newton from zero, chord steps on the
// linear stiffness); then an effect is added, the current fit redone and the next round tested.
TEST(IdentifyScoreReuse, LaterRoundsScoreTestsMatchATestThatReusesNothing) {
  const double q = 450.0;
  analysis::Problem truth = cantilever(q);
  truth.material.youngs_modulus *= 1.15;
  const analysis::Problem prior = cantilever(q);
  std::vector<Marker> markers = beam_markers(prior);
  const auto placements = place_markers(prior.patches, markers, 1e-9).placements;
  const double sigma = 1e-3 * 3.17e-4 * q;
  testing::add_noise(markers,
                     simulate_markers(truth, markers, placements,
                                      {{"geometric_nonlinearity", Eigen::VectorXd::Ones(1)},
                                       {"load_scale", Eigen::VectorXd::Constant(1, 0.2)},
                                       {"rigid_offset", Eigen::Vector3d(2e-4, -1e-4, 1e-3)}}),
                     sigma, 7);

  // Qualified: inside a TEST body, Setup names GoogleTest's misspelling guard.
  identify_loop::Setup setup;
  identify_loop::make_setup(setup, prior, markers, placements, false, [](const std::string&) {});
  const std::vector<Eigen::VectorXd> weights =
      identify_loop::make_weights(setup, sigma, std::vector<bool>(markers.size(), true));
  std::string why;
  const auto nonlinear = make_effect("geometric_nonlinearity", setup.context, &why);
  const auto load_scale = make_effect("load_scale", setup.context, &why);
  const auto rigid_offset = make_effect("rigid_offset", setup.context, &why);
  ASSERT_TRUE(nonlinear && load_scale && rigid_offset) << why;

  // The rounds' current effects: none, then load_scale, then rigid_offset with it.
  const std::vector<std::vector<const Effect*>> rounds = {
      {}, {load_scale.get()}, {load_scale.get(), rigid_offset.get()}};
  Eigen::VectorXd theta = Eigen::VectorXd::Ones(1);
  for (size_t round = 0; round < rounds.size(); ++round) {
    SCOPED_TRACE("round " + std::to_string(round + 1));
    const Model current = identify_loop::build_model(setup, rounds[round], theta);
    const Fit fit =
        identify_loop::run_fit(setup, current, weights, nullptr,
                               round == 0 ? FitStart::kNearOptimum : FitStart::kNewParameters);
    ASSERT_TRUE(fit.ok) << fit.message;
    theta = fit.theta;
    std::vector<const Effect*> with_candidate = rounds[round];
    with_candidate.push_back(nonlinear.get());
    if (round > 0) {
      // What an earlier round left for this one to start from: a solution and a tangent per load
      // case (the large deformation needs tangents: chords on the linear stiffness are too slow).
      for (size_t l = 0; l < 2; ++l) {
        ASSERT_EQ(setup.factorizations->nonlinear_starts.at(l).size(), setup.num_dofs);
        ASSERT_FALSE(setup.factorizations->tangents.at(l).empty()) << "load case " << l;
      }
    }
    const long starts_before = setup.factorizations->kept_tangent_starts;
    const long converged_before = setup.factorizations->kept_tangent_converged;
    const Model reusing = identify_loop::build_model(setup, with_candidate, theta);
    const Model alone =
        identify_loop::build_model(setup, with_candidate, theta, make_factorization_cache());
    const Eigen::VectorXd neutral = nonlinear->screening_values();
    const ScoreTest reused = identify_loop::score_test(setup, reusing, fit, neutral, weights, 0.0);
    const ScoreTest fresh = identify_loop::score_test(setup, alone, fit, neutral, weights, 0.0);
    ASSERT_TRUE(reused.done && fresh.done);
    // Round 1 has nothing to reuse; later rounds solve both load cases on the kept tangents
    // without a factorisation of their own (measured: 8-10 residual evaluations each, against
    // 2-3 tangents each from zero).
    const long kept = round == 0 ? 0 : 2;
    EXPECT_EQ(setup.factorizations->kept_tangent_starts - starts_before, kept);
    EXPECT_EQ(setup.factorizations->kept_tangent_converged - converged_before, kept);
    // Strongly significant: the column is well away from zero, so that a relative comparison
    // of F and the estimate is a comparison of the column's accuracy.
    EXPECT_GT(fresh.f_statistic, 100.0);
    EXPECT_EQ(reused.q, fresh.q);
    EXPECT_EQ(reused.d2, fresh.d2);
    // Without reuse Newton stops at the markers (a contracting chord step that moved them by at
    // most 1e-6 of their displacement), with reuse the chord steps end at the force tolerance:
    // the column in w, a tenth of the displacement here, agrees to ~1e-8 (measured in
    // IdentifyNonlinear.ScoreTestColumnStoppedAtTheMarkersMatchesTheFullTolerance: 2.4e-8).
    // Measured here: F 2.2e-9 and 3.3e-9 (rounds 2 and 3), the RSS reduction 2e-11, the
    // estimate 2.6e-9, its standard error 4e-9, ln p 6e-10.
    expect_relative(reused.f_statistic, fresh.f_statistic, 1e-6, "F");
    expect_relative(reused.reduction, fresh.reduction, 1e-6, "RSS reduction");
    ASSERT_EQ(reused.estimate.size(), 1);
    ASSERT_EQ(fresh.estimate.size(), 1);
    expect_relative(reused.estimate[0], fresh.estimate[0], 1e-6, "estimate of w");
    expect_relative(reused.estimate_error[0], fresh.estimate_error[0], 1e-6, "its error");
    // p (1e-235 and 1e-264: the effect is strong) moves by d ln p / d ln F ~ 115 times F's
    // relative change: measured 2.6e-8 and 3.8e-7.
    ASSERT_GT(fresh.p_value, 0.0);
    expect_relative(std::log(reused.p_value), std::log(fresh.p_value), 1e-6, "ln p");
    expect_relative(reused.p_value, fresh.p_value, 1e-6, "p");
  }
}

}  // namespace
}  // namespace isospring::fitting
