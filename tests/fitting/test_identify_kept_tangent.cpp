// A factorised tangent of the large-deformation model carries the state it was made at
// (KeptTangent): a Jacobian at an equilibrium of the same matrix solves with it instead of a new
// tangent. Checked against the same evaluations without the kept tangents (new caches, Newton
// and a factorisation of their own): a hold-out fold's refit from the loop's fit, a later
// round's score tests of candidates whose neutral values leave the stiffness as it was, and the
// blend's linear factor reused, scaled, after a change of E. The folds' own refits, whose
// Jacobians solve on the tangent at hand, against the exact refit.
#include <gtest/gtest.h>

#include <algorithm>
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

constexpr double kLoad = 450.0;

analysis::Problem cantilever() {
  return testing::two_load_cantilever(kLoad);
}
using testing::beam_markers;

// SVK data (w = 1) with E = 1.15 E_prior, noise 1/1000 of the tip deflection; the loop's setup
// and weights, the large-deformation model fitted on the loop's cache with its covariance (the
// last evaluation of the loop's final fit, which leaves the tangents at the fit in the cache).
class KeptTangentCantilever : public ::testing::Test {
 protected:
  void SetUp() override {
    analysis::Problem truth = prior_;
    truth.material.youngs_modulus *= 1.15;
    markers_ = beam_markers(prior_);
    const auto placements = place_markers(prior_.patches, markers_, 1e-9).placements;
    testing::add_noise(markers_,
                       simulate_markers(truth, markers_, placements,
                                        {{"geometric_nonlinearity", Eigen::VectorXd::Ones(1)}}),
                       kSigma, 11);
    identify_loop::make_setup(setup_, prior_, markers_, placements, false,
                              [](const std::string&) {});
    weights_ =
        identify_loop::make_weights(setup_, kSigma, std::vector<bool>(markers_.size(), true));
    std::string why;
    for (const char* name : {"geometric_nonlinearity", "load_scale", "rigid_offset",
                             "stiffness_gradient", "support_compliance"}) {
      effects_.push_back(make_effect(name, setup_.context, &why));
      ASSERT_TRUE(effects_.back()) << why;
    }
    current_ = std::make_unique<Model>(
        identify_loop::build_model(setup_, {nonlinear()}, Eigen::VectorXd::Ones(1)));
    Eigen::MatrixXd covariance;
    fit_ =
        identify_loop::run_fit(setup_, *current_, weights_, &covariance, FitStart::kNewParameters);
    ASSERT_TRUE(fit_.ok) << fit_.message;
    errors_ = covariance.diagonal().cwiseSqrt() *
              std::sqrt(fit_.rss / static_cast<double>(fit_.rows - fit_.theta.size()));
  }
  const Effect* nonlinear() const { return effects_[0].get(); }
  long tangents() const { return setup_.factorizations->tangent_factorizations; }
  long reuses() const { return setup_.factorizations->kept_state_reuses; }
  // A hold-out fold's fitted half: every other marker of each load case.
  std::vector<bool> every_other_marker() const {
    std::vector<bool> even(markers_.size(), false);
    for (const auto& ids : setup_.markers)
      for (size_t k = 0; k < ids.size(); k += 2) even[static_cast<size_t>(ids[k])] = true;
    return even;
  }
  // A cache with the loop's solutions (Newton's starts) but none of its tangents.
  std::shared_ptr<FactorizationCache> starts_only_cache() const {
    auto cache = make_factorization_cache();
    cache->nonlinear_starts = setup_.factorizations->nonlinear_starts;
    cache->linear_starts = setup_.factorizations->linear_starts;
    return cache;
  }

  static constexpr double kSigma = 1e-3 * 3.17e-4 * kLoad;
  analysis::Problem prior_ = cantilever();
  std::vector<Marker> markers_;
  // Qualified: inside a test, Setup names GoogleTest's misspelling guard.
  identify_loop::Setup setup_;
  std::vector<Eigen::VectorXd> weights_;
  std::vector<std::unique_ptr<Effect>> effects_;
  std::unique_ptr<Model> current_;
  Fit fit_;
  Eigen::VectorXd errors_;  // the fit's standard errors
};

// The largest difference of two evaluations' predictions (relative to the largest prediction)
// and Jacobian columns (each relative to its largest entry).
struct Difference {
  double prediction = 0.0, jacobian = 0.0;
};
Difference difference(const ModelEvaluation& a, const ModelEvaluation& b) {
  Difference d;
  double largest = 0.0;
  for (size_t l = 0; l < b.predictions.size(); ++l)
    largest = std::max(largest, b.predictions[l].cwiseAbs().maxCoeff());
  for (size_t l = 0; l < b.predictions.size(); ++l) {
    d.prediction = std::max(d.prediction,
                            (a.predictions[l] - b.predictions[l]).cwiseAbs().maxCoeff() / largest);
    for (Eigen::Index c = 0; c < b.jacobians[l].cols(); ++c) {
      double column = 0.0;
      for (size_t k = 0; k < b.jacobians.size(); ++k)
        column = std::max(column, b.jacobians[k].col(c).cwiseAbs().maxCoeff());
      if (column > 0.0)
        d.jacobian = std::max(
            d.jacobian,
            (a.jacobians[l].col(c) - b.jacobians[l].col(c)).cwiseAbs().maxCoeff() / column);
    }
  }
  return d;
}

// A hold-out fold (every other marker) refits the final model from the loop's fit, on a cache
// that shares the loop's kept tangents (identify_loop::fold_cache), and on one that has only
// the loop's solutions (the folds before): the same parameters, two tangents fewer (the first
// Jacobian's, one per load case), and the fold's evaluation at its fit (a load-case fold's
// residual) on its own last tangent without a factorisation.
TEST_F(KeptTangentCantilever, AFoldsRefitOnTheLoopsTangentsMatchesOneWithoutThem) {
  const std::vector<bool> even = every_other_marker();
  const auto fold_weights = identify_loop::make_weights(setup_, kSigma, even);

  const auto kept = identify_loop::fold_cache(*setup_.factorizations);
  kept->jacobians_on_kept_tangents = false;  // exact Jacobians (the next test: the folds' own)
  const auto starts_only = starts_only_cache();
  const Model with_kept = identify_loop::build_model(setup_, {nonlinear()}, fit_.theta, kept);
  const Model without = identify_loop::build_model(setup_, {nonlinear()}, fit_.theta, starts_only);
  const Fit a = identify_loop::run_fit(setup_, with_kept, fold_weights);
  const Fit b = identify_loop::run_fit(setup_, without, fold_weights);
  ASSERT_TRUE(a.ok && b.ok) << a.message << " / " << b.message;
  ASSERT_EQ(a.theta.size(), 2);
  // The refit moves the parameters by standard errors (measured: 0.60 of them); both refits
  // end at the same point to far below that, where only the Newton solves' tolerance (1e-10 of
  // the load) and rounding differ: measured 1.1e-11 relative in E and w. The RSS moves by the
  // predictions' difference times the residual over the noise (rows of order 1, noise 1e-3 of
  // the deflection: 1e3 x): measured 9.1e-11 relative.
  EXPECT_GT(((a.theta - fit_.theta).array() / errors_.array()).abs().maxCoeff(), 0.1);
  for (Eigen::Index k = 0; k < 2; ++k)
    EXPECT_LE(std::abs(a.theta[k] - b.theta[k]), 1e-10 * std::abs(b.theta[k]))
        << "parameter " << k << ": " << a.theta[k] << " with the kept tangents, " << b.theta[k]
        << " without";
  EXPECT_LE(std::abs(a.rss - b.rss), 1e-8 * b.rss);
  EXPECT_EQ(a.iterations, b.iterations);
  EXPECT_EQ(kept->kept_state_reuses, 2);
  EXPECT_EQ(starts_only->kept_state_reuses, 0);
  EXPECT_EQ(starts_only->tangent_factorizations - kept->tangent_factorizations, 2);

  const long before = kept->tangent_factorizations;
  const ModelEvaluation at_fit = with_kept.forward->evaluate(a.theta, true);
  EXPECT_EQ(kept->tangent_factorizations, before);
  EXPECT_EQ(kept->kept_state_reuses, 4);
  const auto fresh_cache = make_factorization_cache();
  const Model fresh = identify_loop::build_model(setup_, {nonlinear()}, a.theta, fresh_cache);
  // Against Newton from rest with its own tangents: measured 1.4e-12 (predictions) and 4.0e-11
  // (Jacobian columns), the solves' tolerance and rounding.
  const Difference d = difference(at_fit, fresh.forward->evaluate(a.theta, true));
  EXPECT_LE(d.prediction, 1e-9);
  EXPECT_LE(d.jacobian, 1e-8);
}

// The folds' own refits (identify_loop::fold_cache) take every Jacobian on the tangent at hand:
// no tangent at all, and an optimum within a small fraction of a standard error of the exact
// refit's (where J_k^T r = 0 instead of J^T r = 0, J_k - J of the order of the relative change
// of E). The held-out markers' prediction, what a fold is for, moves by far less than the noise.
TEST_F(KeptTangentCantilever, AFoldsRefitWithJacobiansOnTheKeptTangentEndsNearTheExactOne) {
  const std::vector<bool> even = every_other_marker();
  const auto fold_weights = identify_loop::make_weights(setup_, kSigma, even);
  const auto fold = identify_loop::fold_cache(*setup_.factorizations);
  ASSERT_TRUE(fold->jacobians_on_kept_tangents);
  const auto exact = starts_only_cache();
  const Model on_kept = identify_loop::build_model(setup_, {nonlinear()}, fit_.theta, fold);
  const Model reference = identify_loop::build_model(setup_, {nonlinear()}, fit_.theta, exact);
  const Fit a = identify_loop::run_fit(setup_, on_kept, fold_weights);
  const Fit b = identify_loop::run_fit(setup_, reference, fold_weights);
  ASSERT_TRUE(a.ok && b.ok) << a.message << " / " << b.message;
  EXPECT_EQ(fold->tangent_factorizations, 0);
  EXPECT_GT(fold->jacobians_on_kept_tangent, 0);
  EXPECT_GE(exact->tangent_factorizations, 4);
  const double moved = ((b.theta - fit_.theta).array() / errors_.array()).abs().maxCoeff();
  const double apart = ((a.theta - b.theta).array() / errors_.array()).abs().maxCoeff();
  // Measured: the refit moves by 0.60 standard errors, the two refits end 6.1e-6 of one apart
  // (in 2 iterations each, 0 tangents against 6), and the odd markers' predictions differ by
  // 1.6e-6 of the noise.
  EXPECT_GT(moved, 0.1);
  EXPECT_LE(apart, 1e-3);
  // The odd markers' misfit at either fit.
  const auto misfit_a = identify_loop::marker_misfit(setup_, on_kept, a.theta, markers_);
  const auto misfit_b = identify_loop::marker_misfit(setup_, reference, b.theta, markers_);
  double largest = 0.0;
  for (size_t m = 0; m < markers_.size(); ++m)
    if (!even[m]) largest = std::max(largest, (misfit_a[m] - misfit_b[m]).norm());
  EXPECT_LE(largest, 1e-4 * kSigma);
}

// A later round's score tests add a candidate at its neutral values to the large-deformation
// model: a load factor, a rigid motion and a stiffness gradient leave its stiffness (a gradient
// with a = 0 adds terms with zero coefficients) and its equilibrium as they were, so their
// Jacobians solve on the current model's tangents; a compliant support frees the clamped DOFs
// and needs tangents of its own, after which the next candidate still finds the current
// model's. Each Jacobian matches a new cache's (Newton from rest, its own tangents).
TEST_F(KeptTangentCantilever, NeutralCandidatesSolveOnTheCurrentModelsTangents) {
  // What the loop's round leaves: the current model evaluated at its fit.
  (void)current_->forward->evaluate(fit_.theta, false);
  // load_scale, support_compliance (its own free DOFs), stiffness_gradient, rigid_offset.
  for (const size_t e : {1, 4, 3, 2}) {
    const bool same_stiffness = e != 4;
    const Effect* candidate = effects_[e].get();
    SCOPED_TRACE(candidate->name());
    const std::vector<const Effect*> effects = {nonlinear(), candidate};
    Eigen::VectorXd theta(fit_.theta.size() + candidate->num_parameters());
    theta << fit_.theta, candidate->screening_values();
    const Model model = identify_loop::build_model(setup_, effects, theta);
    const long tangents_before = tangents(), reuses_before = reuses();
    const ModelEvaluation reused = model.forward->evaluate(theta, true);
    if (same_stiffness) {
      EXPECT_EQ(tangents() - tangents_before, 0);
      EXPECT_EQ(reuses() - reuses_before, 2);
    } else {
      EXPECT_GE(tangents() - tangents_before, 2);
      EXPECT_EQ(reuses() - reuses_before, 0);
    }
    const Model alone =
        identify_loop::build_model(setup_, effects, theta, make_factorization_cache());
    // Measured: 1.6e-11 (predictions) and 1.9e-10 (Jacobian columns) on the kept tangents,
    // 3.3e-12 and 5.0e-11 for the compliant support's own.
    const Difference d = difference(reused, alone.forward->evaluate(theta, true));
    EXPECT_LE(d.prediction, 1e-9);
    EXPECT_LE(d.jacobian, 1e-8);
  }
}

// The blend's linear stiffness after a change of E alone is the factorised one scaled: one
// factorisation for both evaluations, and at w = 0 (where the prediction is the linear solution)
// the predictions and the Jacobian's column in E those of a new factorisation, to the rounding of
// two factorisations of proportional matrices (measured 6.6e-12 and 1.1e-11 of the largest
// entry; a solve's relative rounding is up to the condition number of K, ~1e5 here, times 1e-16).
TEST_F(KeptTangentCantilever, TheBlendsLinearFactorServesAChangeOfEScaled) {
  const auto cache = make_factorization_cache();
  const Model model = identify_loop::build_model(setup_, {nonlinear()}, fit_.theta, cache);
  const Eigen::Vector2d first(1.0, 0.0), second(1.3, 0.0);
  (void)model.forward->evaluate(first, true);
  const ModelEvaluation scaled = model.forward->evaluate(second, true);
  EXPECT_EQ(cache->blend_factorizations, 1);
  const auto fresh_cache = make_factorization_cache();
  const Model fresh = identify_loop::build_model(setup_, {nonlinear()}, fit_.theta, fresh_cache);
  const ModelEvaluation direct = fresh.forward->evaluate(second, true);
  EXPECT_EQ(fresh_cache->blend_factorizations, 1);
  for (size_t l = 0; l < direct.predictions.size(); ++l) {
    const double size = direct.predictions[l].cwiseAbs().maxCoeff();
    EXPECT_LE((scaled.predictions[l] - direct.predictions[l]).cwiseAbs().maxCoeff(), 1e-10 * size);
    const double column = direct.jacobians[l].col(0).cwiseAbs().maxCoeff();
    EXPECT_LE((scaled.jacobians[l].col(0) - direct.jacobians[l].col(0)).cwiseAbs().maxCoeff(),
              1e-10 * column);
  }
  // Another Poisson ratio or stiffness term would not be a scale: a model whose E alone moves
  // never factorises again, however far it moves.
  (void)model.forward->evaluate(Eigen::Vector2d(0.7, 0.5), false);
  EXPECT_EQ(cache->blend_factorizations, 1);
}

}  // namespace
}  // namespace isospring::fitting
