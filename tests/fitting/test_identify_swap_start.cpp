// The swap stage's fits start from the candidate's values at its latest fit (swap_start): the
// same optimum as from the candidate's initial values, in fewer factorisations. Uses the loop's
// private stages (fitting/src/identify).
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <iostream>

#include "identify/fit_stopping.hpp"
#include "identify/loop_state.hpp"
#include "isospring/fitting/effect.hpp"
#include "isospring/fitting/identify.hpp"
#include "test_identify_plate.hpp"

namespace isospring::fitting::identify_loop {
namespace {

using testing::add_noise;
using testing::grid_markers;
using testing::plate_problem;

// The plate of test_identify_plate.hpp with markers simulated with a hidden effect beside the
// second load case 8 % heavier (noise 0.2 % of the largest displacement), the loop's setup on
// them and the effects of its library that the tests use.
struct SwapPlate {
  analysis::Problem problem = plate_problem(16, 6);
  std::vector<Marker> markers = grid_markers(problem);
  double sigma = 0.0;
  Setup setup;
  std::unique_ptr<Effect> gradient, compliance, load_scale, rigid_offset;

  explicit SwapPlate(const std::string& hidden = "stiffness_gradient",
                     const Eigen::VectorXd& values = Eigen::Vector2d(0.5, -0.3)) {
    const PlacementResult placed = place_markers(problem.patches, markers, 1e-9);
    const auto clean = simulate_markers(problem, markers, placed.placements,
                                        {{hidden, values}, {"load_scale", kLoadScale}});
    double largest = 0.0;
    for (const auto& u : clean) largest = std::max(largest, u.cwiseAbs().maxCoeff());
    sigma = 2e-3 * largest;
    add_noise(markers, clean, sigma, 5);
    make_setup(setup, problem, markers, placed.placements, false, nullptr);
    setup.negligible_rss = kNegligibleRss;
    std::string why;
    gradient = make_effect("stiffness_gradient", setup.context, &why);
    compliance = make_effect("support_compliance", setup.context, &why);
    load_scale = make_effect("load_scale", setup.context, &why);
    rigid_offset = make_effect("rigid_offset", setup.context, &why);
  }
  std::vector<Eigen::VectorXd> weights() const {
    return make_weights(setup, sigma, std::vector<bool>(markers.size(), true));
  }
  // The fit of `effects` from `start` on a cache of its own, and the factorisations it took.
  Fit fit(const std::vector<const Effect*>& effects, const Eigen::VectorXd& start,
          long* factorizations = nullptr, Eigen::MatrixXd* covariance = nullptr) {
    const auto cache = make_factorization_cache();
    const Model model = build_model(setup, effects, start, cache);
    const Fit out = run_fit(setup, model, weights(), covariance, FitStart::kNewParameters);
    if (factorizations) *factorizations = factorization_stats(*cache).factorizations;
    return out;
  }
  inline static const Eigen::VectorXd kLoadScale = Eigen::VectorXd::Constant(1, 0.08);
};

// The swap stage's fit of `candidate` in the rigid offset's place, from the candidate's initial
// values and from its values in a forward round's fit beside the rigid offset (as on the suite's
// frame-and-gravity dataset: the selection holds the rigid offset and the load scale), against
// the same fit run to Ceres' tolerances.
struct SwapFits {
  Fit cold, warm, converged;
  long cold_factorizations = 0, warm_factorizations = 0;
  Eigen::MatrixXd covariance;

  SwapFits(SwapPlate& plate, const Effect* candidate) {
    Selection selection;
    selection.chosen = {plate.rigid_offset.get()};
    const Fit offset = plate.fit(selection.chosen, Eigen::VectorXd::Ones(1));
    EXPECT_TRUE(offset.ok) << offset.message;
    // The forward round's fit of the candidate, recorded as try_candidate does.
    const Fit round = plate.fit({plate.rigid_offset.get(), candidate}, offset.theta);
    EXPECT_TRUE(round.ok) << round.message;
    selection.fitted_values[candidate] = round.theta.tail(candidate->num_parameters());
    // The selection after a later round added the load scale.
    selection.chosen.push_back(plate.load_scale.get());
    selection.current_fit = plate.fit(selection.chosen, offset.theta);
    EXPECT_TRUE(selection.current_fit.ok) << selection.current_fit.message;
    selection.current = build_model(plate.setup, selection.chosen, selection.current_fit.theta);

    const std::vector<const Effect*> swapped = {candidate, plate.load_scale.get()};
    const Eigen::VectorXd cold_start =
        start_replacing(plate.setup, selection.current, selection.current_fit.theta, 0, candidate);
    cold = plate.fit(swapped, cold_start, &cold_factorizations);
    warm =
        plate.fit(swapped, swap_start(plate.setup, selection, 0, candidate), &warm_factorizations);
    plate.setup.negligible_rss = 0.0;
    converged = plate.fit(swapped, cold_start, nullptr, &covariance);
    plate.setup.negligible_rss = kNegligibleRss;
    std::cout << candidate->name() << " in the rigid offset's place: " << cold_factorizations
              << " factorisations from its initial values, " << warm_factorizations
              << " from the round's values\n";
  }
  // Both fits end at the converged optimum within the stopping rule's resolution: RSS within
  // 1e-3 residual variances, parameters within 1e-3 squared standard errors.
  void expect_same_optimum() const {
    ASSERT_TRUE(cold.ok) << cold.message;
    ASSERT_TRUE(warm.ok) << warm.message;
    ASSERT_TRUE(converged.ok) << converged.message;
    const double s2 = converged.rss / static_cast<double>(converged.rows - converged.theta.size());
    for (const Fit* fit : {&cold, &warm}) {
      EXPECT_GE(fit->rss, converged.rss - 1e-9 * converged.rss);
      EXPECT_LT(fit->rss - converged.rss, kNegligibleRss * s2);
      const Eigen::VectorXd d = fit->theta - converged.theta;
      EXPECT_LT(d.dot(covariance.ldlt().solve(d)), kNegligibleRss * s2);
    }
  }
  // The converged fit finds the simulated values within 3 standard errors each.
  void expect_simulated(const Eigen::VectorXd& expected) const {
    for (Eigen::Index k = 0; k < expected.size(); ++k)
      EXPECT_LT(std::abs(converged.theta[k] - expected[k]), 3.0 * std::sqrt(covariance(k, k)))
          << "parameter " << k;
  }
};

// swap_start takes the candidate's recorded values into its place in the swapped model (the
// other parameters from the current fit), inside the candidate's bounds; without a record it is
// start_replacing.
TEST(SwapStart, PutsTheCandidatesFittedValuesInItsPlace) {
  SwapPlate plate;
  std::string why;
  const auto compliance = make_effect("support_compliance", plate.setup.context, &why);
  ASSERT_TRUE(compliance) << why;
  Selection selection;
  selection.chosen = {plate.rigid_offset.get(), plate.load_scale.get()};
  selection.current_fit.theta.resize(1 + 3 + 1);
  selection.current_fit.theta << 1.1, 1e-6, -2e-6, 3e-5, 0.07;
  selection.current = build_model(plate.setup, selection.chosen, selection.current_fit.theta);
  ASSERT_EQ(selection.current.initial.size(), selection.current_fit.theta.size());

  const Eigen::VectorXd cold = swap_start(plate.setup, selection, 0, compliance.get());
  EXPECT_EQ(cold, start_replacing(plate.setup, selection.current, selection.current_fit.theta, 0,
                                  compliance.get()));
  selection.fitted_values[compliance.get()] = Eigen::Vector3d(2.0, 3.0, 1.5);
  const Eigen::VectorXd warm = swap_start(plate.setup, selection, 0, compliance.get());
  ASSERT_EQ(warm.size(), 1 + 3 + 1);
  Eigen::VectorXd expected(5);
  expected << 1.1, 2.0, 3.0, 0.0, 0.07;
  EXPECT_EQ(warm, expected);
  // The second effect replaced: the candidate after the kept rigid offset.
  const Eigen::VectorXd second = swap_start(plate.setup, selection, 1, compliance.get());
  ASSERT_EQ(second.size(), 1 + 3 + 3);
  EXPECT_EQ(second.head(4), selection.current_fit.theta.head(4));
  EXPECT_EQ(second.tail(3), Eigen::Vector3d(2.0, 3.0, 0.0));
  // A spring stiffer than the nearly rigid start restarts there, and the stiffness ratio on its
  // bound (Effect::restart_values).
  selection.fitted_values[compliance.get()] = Eigen::Vector3d(680.0, 3.0, 0.5);
  EXPECT_EQ(swap_start(plate.setup, selection, 0, compliance.get()).segment(1, 3),
            Eigen::Vector3d(std::log(100.0), 3.0, 0.0));
  // A record of another size or with a non-finite value is not used.
  selection.fitted_values[compliance.get()] = Eigen::Vector2d(2.0, 3.0);
  EXPECT_EQ(swap_start(plate.setup, selection, 0, compliance.get()), cold);
  selection.fitted_values[compliance.get()] = Eigen::Vector3d(2.0, NAN, 0.0);
  EXPECT_EQ(swap_start(plate.setup, selection, 0, compliance.get()), cold);
}

// A compliant clamp (springs 20 and 10 x the body's stiffness over its length) starts from
// nearly rigid springs (100 x): from the round's values its swap fit ends at the same optimum in
// fewer factorisations.
TEST(SwapStart, ComplianceSwapFitFromTheRoundsValuesNeedsFewerFactorisations) {
  const Eigen::Vector3d truth(std::log(20.0), std::log(10.0), 0.0);
  SwapPlate plate("support_compliance", truth);
  const SwapFits fits(plate, plate.compliance.get());
  fits.expect_same_optimum();
  EXPECT_LT(fits.warm_factorizations, fits.cold_factorizations);
  Eigen::VectorXd expected(5);
  expected << 1.0, truth, SwapPlate::kLoadScale;
  expected[3] = fits.converged.theta[3];  // log(k_a / k_n) = 0 is its bound: not tested here
  fits.expect_simulated(expected);
}

// A graded modulus from the round's gradient (a rigid offset beside it took part of the
// response): the same optimum as from a = 0.
TEST(SwapStart, GradientSwapFitFromTheRoundsValuesReachesTheSameOptimum) {
  SwapPlate plate;
  const SwapFits fits(plate, plate.gradient.get());
  fits.expect_same_optimum();
  EXPECT_LE(fits.warm_factorizations, fits.cold_factorizations);
  fits.expect_simulated(Eigen::Vector4d(1.0, 0.5, -0.3, 0.08));
}

}  // namespace
}  // namespace isospring::fitting::identify_loop
