// The loop on synthetic data with undeclared effects: data from the forward model with a true E
// 15% above the prior and hidden effects, plus Gaussian noise. The identification must find
// exactly the hidden effects, estimate every parameter within 3 standard errors of the truth and
// leave a residual at the noise level; on pure noise it must add nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

#include "isospring/fitting/identify.hpp"
#include "isospring/nurbs/error.hpp"
#include "test_identify_plate.hpp"

namespace isospring::fitting {
namespace {

using Effects = std::vector<std::pair<std::string, Eigen::VectorXd>>;
constexpr double kSigma = 1e-6;      // noise [m]; the displacements are 1e-4 .. 1e-3 m
constexpr double kTrueScale = 1.15;  // E_true / E_prior

struct Synthetic {
  analysis::Problem prior;
  std::vector<Marker> markers;
  std::vector<MarkerPlacement> placements;
};

Synthetic make_data(const Effects& hidden, unsigned seed, double true_nu = 0.3) {
  Synthetic data;
  data.prior = testing::plate_problem();
  data.markers = testing::grid_markers(data.prior);
  const PlacementResult placed = place_markers(data.prior.patches, data.markers, 1e-9);
  data.placements = placed.placements;
  analysis::Problem truth = data.prior;
  truth.material.youngs_modulus *= kTrueScale;
  truth.material.poisson_ratio = true_nu;
  testing::add_noise(data.markers, simulate_markers(truth, data.markers, data.placements, hidden),
                     kSigma, seed);
  return data;
}

const ParameterEstimate* find(const IdentifyResult& r, const std::string& effect, size_t k) {
  size_t seen = 0;
  for (const auto& p : r.parameters)
    if (p.effect == effect && seen++ == k) return &p;
  return nullptr;
}

void expect_identified(const Effects& hidden, unsigned seed = 1, double true_nu = 0.3,
                       bool fit_poisson = false, const std::vector<std::string>& candidates = {}) {
  const Synthetic data = make_data(hidden, seed, true_nu);
  IdentifyOptions options;
  // Data simulated on this very discretisation: it has no discretisation error to control.
  options.discretization.enabled = false;
  options.holdout = false;
  options.fit_poisson = fit_poisson;
  if (!candidates.empty()) options.candidates = candidates;
  const IdentifyResult r = identify(data.prior, data.markers, data.placements, options);
  std::set<std::string> expected, found(r.effects_added.begin(), r.effects_added.end());
  for (const auto& [name, values] : hidden) expected.insert(name);
  EXPECT_EQ(found, expected);
  // The estimated noise level is close to the true one, the residual at the noise level.
  EXPECT_NEAR(r.noise_estimate, kSigma, 0.15 * kSigma);
  EXPECT_LT(r.after.rms, 1.3 * kSigma);
  EXPECT_GT(r.before.rms, 1.3 * kSigma);  // the hidden effect was visible
  ASSERT_FALSE(r.parameters.empty());
  const ParameterEstimate& e = r.parameters[0];
  EXPECT_LT(std::abs(e.value - kTrueScale * 1e6), 3 * e.standard_error) << "E";
  if (fit_poisson) {
    ASSERT_GT(r.parameters.size(), 1u);
    const ParameterEstimate& nu = r.parameters[1];
    ASSERT_EQ(nu.name, "nu");
    EXPECT_GT(nu.standard_error, 0.0);
    EXPECT_LT(std::abs(nu.value - true_nu), 3 * nu.standard_error)
        << "nu = " << nu.value << " +- " << nu.standard_error;
  }
  if (found != expected) return;
  for (const auto& [name, values] : hidden)
    for (Eigen::Index k = 0; k < values.size(); ++k) {
      const ParameterEstimate* p = find(r, name, static_cast<size_t>(k));
      ASSERT_NE(p, nullptr);
      EXPECT_GT(p->standard_error, 0.0);
      // Support stiffnesses are fitted relative to E_prior / L, the generator's to E_true / L.
      // (log(k_a / k_n) is a ratio: the same for both.)
      const double truth =
          values[k] + (name == "support_compliance" && k < 2 ? std::log(kTrueScale) : 0.0);
      EXPECT_LT(std::abs(p->value - truth), 3 * p->standard_error)
          << name << "." << p->name << " = " << p->value << " +- " << p->standard_error
          << ", truth " << truth;
    }
}

const Eigen::VectorXd kGravity = Eigen::Vector2d(0.0, -9.81);
// Spring stiffnesses (normal, tangential) 20 and 10 times E_true / L (the generator's reference
// stiffness), log(k_a / k_n) = 0: one normal stiffness for the whole side (the lower bound).
const Eigen::VectorXd kCompliance = Eigen::Vector3d(std::log(20.0), std::log(10.0), 0.0);
// Springs as stiff as E_true / L and half that: the clamp deforms, not only moves.
const Eigen::VectorXd kSoftCompliance = Eigen::Vector3d(0.0, std::log(0.5), 0.0);
// A confined layer: the uniform normal displacement (the tension's) 8 x stiffer than rocking
// (the shear's bending). With one normal stiffness the tension's remainder would read as a
// scaled load.
const Eigen::VectorXd kConfinedCompliance =
    Eigen::Vector3d(std::log(2.0), std::log(1.0), std::log(8.0));
const Eigen::VectorXd kGradient = Eigen::Vector2d(0.3, -0.2);
// One rigid motion of the measuring frame for both load cases (tx, ty, rz), and a different one
// per load case.
const Eigen::VectorXd kOffset = Eigen::Vector3d(3e-6, -2e-6, 4e-5);
const Eigen::VectorXd kOffsetPerLoad =
    (Eigen::VectorXd(6) << 3e-6, -2e-6, 4e-5, -1e-6, 3e-6, -2e-5).finished();
const Eigen::VectorXd kLoadScale = Eigen::VectorXd::Constant(1, 0.05);

TEST(IdentifyEffects, FindsGravity) {
  expect_identified({{"gravity", kGravity}});
}
TEST(IdentifyEffects, FindsSupportCompliance) {
  expect_identified({{"support_compliance", kCompliance}});
}
TEST(IdentifyEffects, FindsStiffnessGradient) {
  expect_identified({{"stiffness_gradient", kGradient}});
}
TEST(IdentifyEffects, FindsRigidOffset) {
  expect_identified({{"rigid_offset", kOffset}});
}
TEST(IdentifyEffects, FindsRigidOffsetPerLoadCase) {
  expect_identified({{"rigid_offset_per_load", kOffsetPerLoad}});
}
TEST(IdentifyEffects, FindsLoadScale) {
  expect_identified({{"load_scale", kLoadScale}});
}
TEST(IdentifyEffects, FindsGravityAndRigidOffset) {
  expect_identified({{"gravity", kGravity}, {"rigid_offset", kOffset}});
}
TEST(IdentifyEffects, FindsStiffnessGradientAndLoadScale) {
  expect_identified({{"stiffness_gradient", kGradient}, {"load_scale", kLoadScale}});
}

TEST(IdentifyEffects, FindsConfinedSupportComplianceAndNoLoadScale) {
  expect_identified({{"support_compliance", kConfinedCompliance}});
}
TEST(IdentifyEffects, FindsSoftSupportComplianceAndGravity) {
  expect_identified({{"support_compliance", kSoftCompliance}, {"gravity", kGravity}});
}
TEST(IdentifyEffects, StiffSupportComplianceIsToldFromRigidMotionsByTheSwapStage) {
  // Springs 10-20 x E / L mostly translate and rotate the plate about the clamp: per load case
  // that is a rigid motion, and in the first round (gravity not yet in the model)
  // rigid_offset_per_load (6 parameters) explains more than support_compliance (3 parameters)
  // can. Forward selection alone ends with gravity + rigid_offset_per_load, at the noise level.
  // The swap stage puts support_compliance in the rigid motions' place: the same fit with 3
  // parameters less, a BIC lower by far more than 2. Everything is then recovered within 3
  // standard errors (expect_identified).
  const Effects hidden{{"support_compliance", kCompliance}, {"gravity", kGravity}};
  const Synthetic data = make_data(hidden, 1);
  IdentifyOptions options;
  // Data simulated on this very discretisation: it has no discretisation error to control.
  options.discretization.enabled = false;
  options.holdout = false;
  const IdentifyResult r = identify(data.prior, data.markers, data.placements, options);
  ASSERT_FALSE(r.rounds.empty());
  EXPECT_EQ(r.rounds[0].added, "rigid_offset_per_load");  // the premise: the path goes wrong
  bool swapped = false;
  for (const Alternative& a : r.alternatives)
    if (a.swapped && a.replaced == "rigid_offset_per_load" && a.by == "support_compliance") {
      swapped = true;
      EXPECT_LT(a.delta_bic, -10.0);
    }
  EXPECT_TRUE(swapped);
  EXPECT_LT(r.after.rms, 1.3 * kSigma);
  expect_identified(hidden, 1);
}
TEST(IdentifyEffects, FindsSoftSupportComplianceAndRigidOffset) {
  expect_identified({{"support_compliance", kSoftCompliance}, {"rigid_offset", kOffset}});
}
TEST(IdentifyEffects, FindsGravityWithPoissonRatioFitted) {
  // True nu 0.25 against the prior's 0.3: the lateral contraction under tension fixes it.
  expect_identified({{"gravity", kGravity}}, 1, 0.25, true);
}

TEST(IdentifyEffects, AddsNothingToPureNoiseIn19Of20Seeds) {
  // The Bonferroni-corrected F-test at 1% adds a spurious effect with probability <= 1% per
  // seed; 2 or more false additions in 20 seeds would happen with probability < 2%.
  int clean = 0;
  double worst_e_error = 0.0;
  for (unsigned seed = 100; seed < 120; ++seed) {
    const Synthetic data = make_data({}, seed);
    IdentifyOptions options;
    // Data simulated on this very discretisation: it has no discretisation error to control.
    options.discretization.enabled = false;
    options.holdout = false;
    const IdentifyResult r = identify(data.prior, data.markers, data.placements, options);
    if (r.effects_added.empty()) ++clean;
    worst_e_error = std::max(worst_e_error, std::abs(r.parameters[0].value - kTrueScale * 1e6) /
                                                r.parameters[0].standard_error);
    EXPECT_LT(r.after.rms, 1.3 * kSigma);
  }
  EXPECT_GE(clean, 19);
  EXPECT_LT(worst_e_error, 3.5);  // max of 20 |z| values
}

TEST(IdentifyEffects, HoldoutImprovesWhenTheEffectIsReal) {
  const Synthetic data = make_data({{"gravity", kGravity}}, 3);
  IdentifyOptions options;
  options.discretization.enabled = false;  // data simulated on this very discretisation
  const IdentifyResult r = identify(data.prior, data.markers, data.placements, options);
  ASSERT_TRUE(r.holdout_done);
  EXPECT_EQ(r.holdout.validation_markers + r.holdout.fit_markers,
            static_cast<int>(data.markers.size()));
  // Validation residual drops from the misfit to the noise level.
  EXPECT_LT(r.holdout.validation_after.rms, 1.3 * kSigma);
  EXPECT_GT(r.holdout.validation_before.rms, 2 * r.holdout.validation_after.rms);
}

// Every candidate is fitted only when a score test at the current fit does not rule it out
// (identify_selection.cpp). The test's one Gauss-Newton step must predict what the fit then
// finds: for gravity, linear in its parameters, the two F statistics agree closely.
TEST(IdentifyEffects, ScoreScreeningOfALinearCandidateAgreesWithItsFit) {
  const Synthetic data = make_data({{"gravity", kGravity}}, 5);
  IdentifyOptions options;
  options.discretization.enabled = false;  // data simulated on this very discretisation
  options.holdout = false;
  const IdentifyResult r = identify(data.prior, data.markers, data.placements, options);
  ASSERT_FALSE(r.rounds.empty());
  const CandidateTest* gravity = nullptr;
  for (const CandidateTest& c : r.rounds[0].candidates)
    if (c.effect == "gravity") gravity = &c;
  ASSERT_NE(gravity, nullptr);
  ASSERT_TRUE(gravity->note.empty()) << gravity->note;  // fitted, not screened out
  ASSERT_TRUE(std::isfinite(gravity->score_f));
  EXPECT_GT(gravity->f_statistic, 100.0);
  EXPECT_NEAR(gravity->score_f / gravity->f_statistic, 1.0, 0.05)
      << "score F " << gravity->score_f << ", fit F " << gravity->f_statistic;
  // On these data nothing else is significant: the other candidates of the last round were
  // ruled out by their score tests, without a fit.
  for (const CandidateTest& c : r.rounds.back().candidates) {
    if (c.effect != "gravity" && c.p_value > 10.0 * options.significance) {
      EXPECT_NE(c.note.find("screened out"), std::string::npos) << c.effect << ": " << c.note;
    }
  }
}

// The hold-out folds run on several threads, each with its own factorisation cache: the same
// numbers as on one thread.
TEST(IdentifyEffects, HoldoutFoldsOnTwoThreadsMatchOneThread) {
  const Synthetic data = make_data({{"stiffness_gradient", kGradient}}, 4);
  IdentifyOptions options;
  options.discretization.enabled = false;  // data simulated on this very discretisation
  options.threads = 1;
  const IdentifyResult one = identify(data.prior, data.markers, data.placements, options);
  options.threads = 2;
  const IdentifyResult two = identify(data.prior, data.markers, data.placements, options);
  ASSERT_TRUE(one.holdout_done && two.holdout_done);
  EXPECT_NEAR(two.holdout.validation_after.rms, one.holdout.validation_after.rms,
              1e-9 * one.holdout.validation_after.rms);
  EXPECT_NEAR(two.holdout.validation_before.rms, one.holdout.validation_before.rms,
              1e-9 * one.holdout.validation_before.rms);
  ASSERT_EQ(one.load_case_holdout.size(), data.prior.load_cases.size());
  ASSERT_EQ(two.load_case_holdout.size(), one.load_case_holdout.size());
  for (size_t l = 0; l < one.load_case_holdout.size(); ++l) {
    EXPECT_EQ(two.load_case_holdout[l].id, one.load_case_holdout[l].id);
    EXPECT_NEAR(two.load_case_holdout[l].after.rms, one.load_case_holdout[l].after.rms,
                1e-9 * one.load_case_holdout[l].after.rms);
    EXPECT_NEAR(two.load_case_holdout[l].before.rms, one.load_case_holdout[l].before.rms,
                1e-9 * one.load_case_holdout[l].before.rms);
  }
}

// Component weights: with noise 100x smaller in y than in x, weights 1 / sigma_c are the
// statistically right ones (the minimum-variance estimate); the fit must use them: estimates
// within 3 standard errors of the truth and standard errors smaller than with equal weights.
// Only the weights' ratios matter, and "mean_abs" weights are 1 / mean |u_c| normalised.
TEST(IdentifyEffects, ComponentWeightsWeighTheComponents) {
  Synthetic data = make_data({}, 11, 0.25);
  analysis::Problem truth = data.prior;
  truth.material.youngs_modulus *= kTrueScale;
  truth.material.poisson_ratio = 0.25;
  const auto exact = simulate_markers(truth, data.markers, data.placements, {});
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (size_t m = 0; m < data.markers.size(); ++m) {
    data.markers[m].displacement = exact[m];
    data.markers[m].displacement.x() += kSigma * noise(rng);
    data.markers[m].displacement.y() += 0.01 * kSigma * noise(rng);
  }
  IdentifyOptions options;
  options.discretization.enabled = false;
  options.holdout = false;
  options.fit_poisson = true;
  options.candidates = std::vector<std::string>{};  // the nominal fit alone
  const IdentifyResult equal = identify(data.prior, data.markers, data.placements, options);
  options.component_weights = {1.0, 100.0};
  const IdentifyResult weighted = identify(data.prior, data.markers, data.placements, options);
  ASSERT_EQ(weighted.parameters.size(), 2u);
  ASSERT_EQ(weighted.parameters_before.size(), 2u);
  EXPECT_TRUE(weighted.effects_added.empty());
  const double truths[2] = {kTrueScale * 1e6, 0.25};
  for (size_t k = 0; k < 2; ++k) {
    const ParameterEstimate& p = weighted.parameters[k];
    EXPECT_LT(std::abs(p.value - truths[k]), 3 * p.standard_error) << p.name;
    EXPECT_LT(p.standard_error, 0.5 * equal.parameters[k].standard_error) << p.name;
  }
  ASSERT_EQ(weighted.component_weights.size(), 2u);
  EXPECT_NEAR(weighted.component_weights[1] / weighted.component_weights[0], 100.0, 1e-12);
  EXPECT_NEAR(std::hypot(weighted.component_weights[0], weighted.component_weights[1]),
              std::sqrt(2.0), 1e-12);  // rms 1
  options.component_weights = {3.0, 300.0};
  const IdentifyResult scaled = identify(data.prior, data.markers, data.placements, options);
  for (size_t k = 0; k < 2; ++k)
    EXPECT_NEAR(scaled.parameters[k].value / weighted.parameters[k].value, 1.0, 1e-9);

  options.component_weights.clear();
  options.component_weights_mean_abs = true;
  const IdentifyResult mean_abs = identify(data.prior, data.markers, data.placements, options);
  double mx = 0.0, my = 0.0;
  for (const Marker& m : data.markers)
    mx += std::abs(m.displacement.x()), my += std::abs(m.displacement.y());
  ASSERT_EQ(mean_abs.component_weights.size(), 2u);
  EXPECT_NEAR(mean_abs.component_weights[1] / mean_abs.component_weights[0], mx / my,
              1e-9 * mx / my);

  options.component_weights = {1.0, 2.0};  // both: an input error
  EXPECT_THROW(identify(data.prior, data.markers, data.placements, options), nurbs::InputError);
  options.component_weights_mean_abs = false;
  options.component_weights = {1.0, 2.0, 3.0};  // three weights for a 2D model
  EXPECT_THROW(identify(data.prior, data.markers, data.placements, options), nurbs::InputError);
  options.component_weights = {1.0, -2.0};
  EXPECT_THROW(identify(data.prior, data.markers, data.placements, options), nurbs::InputError);
}

TEST(IdentifyEffects, UnknownLoadCaseIsAnInputError) {
  Synthetic data = make_data({}, 5);
  data.markers[3].load_case = "L9";
  try {
    identify(data.prior, data.markers, data.placements);
    FAIL() << "expected an InputError";
  } catch (const nurbs::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("row 5"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("L9"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace isospring::fitting
