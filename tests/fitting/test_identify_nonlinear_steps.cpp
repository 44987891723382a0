// The nonlinear forward model's load stepping: a model that cannot carry a small fraction of its
// load from rest fails after a bounded number of Newton iterations (the ladder of 1, 2, 4, ...
// load steps stops there), and a load too large for Newton from rest still converges with steps.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>

#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/dof_map.hpp"
#include "isospring/analysis/elasticity.hpp"
#include "isospring/analysis/nonlinear_elasticity.hpp"
#include "isospring/analysis/post_processing.hpp"
#include "isospring/fitting/effect.hpp"
#include "isospring/fitting/identify.hpp"
#include "test_identify_plate.hpp"

namespace isospring::fitting {
namespace {

// Calls of a nonlinear term: residuals (without tangent), tangents, and residuals at rest (u = 0:
// the first iterate of a load-stepping attempt).
struct Counts {
  std::atomic<int> residuals{0}, tangents{0}, at_rest{0};
  void reset() { residuals = 0, tangents = 0, at_rest = 0; }
};

// Wraps a nonlinear term's evaluate so that its calls are counted: every Newton or chord
// iteration evaluates the residual once, every Newton step assembles one tangent.
void count_calls(NonlinearTerm& term, const std::shared_ptr<Counts>& counts) {
  auto inner = term.evaluate;
  term.evaluate = [inner, counts](const Eigen::VectorXd& u, const std::vector<double>& e,
                                  std::vector<Eigen::VectorXd>& parts,
                                  Eigen::SparseMatrix<double>* tangent) {
    ++(tangent ? counts->tangents : counts->residuals);
    if (!tangent && u.isZero(0.0)) ++counts->at_rest;
    inner(u, e, parts, tangent);
  };
}

// One DOF with linear stiffness k and a nonlinear internal force r(u) (its part beyond the
// linear one, r(u) - k u, is the model's nonlinear term with coefficient 1). theta = (w, load).
// `cache`: shared with other models (their kept solutions and tangents), else one of its own.
std::unique_ptr<ForwardModel> one_dof(double (*r)(double), double (*dr)(double),
                                      const std::shared_ptr<Counts>& counts, double k = 1.0,
                                      std::shared_ptr<FactorizationCache> cache = nullptr) {
  ModelTerms terms;
  terms.num_parameters = 2;
  Eigen::SparseMatrix<double> stiffness(1, 1);
  stiffness.insert(0, 0) = k;
  terms.stiffness.push_back({stiffness, constant_coefficient(1.0)});
  const Coefficient load = [](const Eigen::VectorXd& theta, Eigen::VectorXd* gradient) {
    if (gradient) *gradient = Eigen::Vector2d(0.0, 1.0);
    return theta[1];
  };
  terms.loads.push_back({0, Eigen::VectorXd::Ones(1), load});
  NonlinearTerm term;
  term.coefficients = {constant_coefficient(1.0)};
  term.evaluate = [r, dr, k](const Eigen::VectorXd& u, const std::vector<double>& e,
                             std::vector<Eigen::VectorXd>& parts,
                             Eigen::SparseMatrix<double>* tangent) {
    parts.assign(1, Eigen::VectorXd::Constant(1, r(u[0]) - k * u[0]));
    if (tangent) {
      tangent->resize(1, 1);
      tangent->insert(0, 0) = e[0] * (dr(u[0]) - k);
    }
  };
  count_calls(term, counts);
  terms.nonlinear.push_back(std::move(term));
  terms.nonlinear_weight = 0;
  Observation all;
  all.operator_.resize(1, 1);
  all.operator_.setIdentity();
  return std::make_unique<ForwardModel>(std::move(terms), std::vector<Observation>{all},
                                        std::vector<int>{}, std::vector<double>{}, 1, 1,
                                        std::move(cache));
}

// A saturating force, r = tanh(u): no equilibrium above the limit load 1, and Newton from rest
// runs away there (the tangent 1 / cosh^2 vanishes).
double saturating(double u) {
  return std::tanh(u);
}
double saturating_tangent(double u) {
  return 1.0 / (std::cosh(u) * std::cosh(u));
}
// A stiffening force, r = sinh(u): Newton from rest starts at the linear solution u = f, far
// beyond the equilibrium asinh(f) for a large load, and comes back by about 1 per iteration.
double stiffening(double u) {
  return std::sinh(u);
}
double stiffening_tangent(double u) {
  return std::cosh(u);
}
// A cubic force, r = u + u^3, for the rounding floor below.
double cubic(double u) {
  return u + u * u * u;
}
double cubic_tangent(double u) {
  return 1.0 + 3.0 * u * u;
}

// w = 1 (the nonlinear model) and the load.
Eigen::VectorXd on(double load) {
  return Eigen::Vector2d(1.0, load);
}

// Below the limit load the spring converges (to tanh(u) = f, u = atanh(f)); 100 x above it,
// where not even the ladder's smallest step of 1/64 can be carried, the evaluation fails (an
// error the fit reads as a failed step) after 4 attempts from rest: the full load, then 2, 4 and
// 8 steps, whose first steps of 1/2, 1/4 and 1/8 of the load fail; each attempt at most 31
// residuals and 30 tangents. Without the stop, the ladder went on to 16, 32 and 64 steps.
TEST(IdentifyNonlinearSteps, AModelThatCannotCarryASmallStepFailsFast) {
  const auto counts = std::make_shared<Counts>();
  const double solvable = 0.9;
  EXPECT_NEAR(one_dof(saturating, saturating_tangent, counts)
                  ->evaluate(on(solvable), false)
                  .predictions[0][0],
              std::atanh(solvable), 1e-9);
  EXPECT_EQ(counts->at_rest.load(), 1);  // converged from rest at the full load
  counts->reset();
  EXPECT_THROW(one_dof(saturating, saturating_tangent, counts)->evaluate(on(100.0), false),
               std::runtime_error);
  EXPECT_EQ(counts->at_rest.load(), 4);
  EXPECT_LE(counts->residuals.load(), 4 * 31);
  EXPECT_LE(counts->tangents.load(), 4 * 30);
}

// Load 40 on the stiffening spring: Newton from rest starts at the linear solution u = f, far
// beyond the equilibrium asinh(f), and comes back by about 1 per Newton step (a slow chord step
// before each of them costs one more residual): more than its 30 iterations at the full load and
// at half of it, fewer at a quarter, and each later step starts from the last equilibrium. So
// the ladder must go on past the failed first steps of 1 and 1/2 of the load and converge with 4.
TEST(IdentifyNonlinearSteps, ALoadTooLargeForNewtonFromRestConvergesWithSteps) {
  const auto counts = std::make_shared<Counts>();
  const double load = 40.0;
  const ModelEvaluation out =
      one_dof(stiffening, stiffening_tangent, counts)->evaluate(on(load), true);
  EXPECT_NEAR(out.predictions[0][0], std::asinh(load), 1e-9 * std::asinh(load));
  // The Jacobian in w at w = 1: u_nl - u_lin.
  EXPECT_NEAR(out.jacobians[0](0, 0), std::asinh(load) - load, 1e-9 * load);
  // du/dload = 1 / cosh(u) at the equilibrium (implicit function theorem).
  EXPECT_NEAR(out.jacobians[0](0, 1), 1.0 / std::cosh(std::asinh(load)), 1e-9);
  EXPECT_EQ(counts->at_rest.load(), 3);  // the full load, then 2 and 4 steps
  EXPECT_GT(counts->residuals.load(), 2 * 30);
}

// A model that converged before starts Newton from its own last equilibrium; when that fails
// (a fit's trial step too long: here the load jumps from 1 to 40), the evaluation fails at once,
// without load steps from rest, for the fit to try a shorter step; and that shorter step (a load
// of 2) converges from the same equilibrium.
TEST(IdentifyNonlinearSteps, ATrialFromTheLastEquilibriumFailsWithoutTheLadder) {
  const auto counts = std::make_shared<Counts>();
  const auto model = one_dof(stiffening, stiffening_tangent, counts);
  EXPECT_NEAR(model->evaluate(on(1.0), false).predictions[0][0], std::asinh(1.0), 1e-9);
  counts->reset();
  EXPECT_THROW(model->evaluate(on(40.0), false), std::runtime_error);
  EXPECT_EQ(counts->at_rest.load(), 0);
  EXPECT_LE(counts->residuals.load(), 31);
  EXPECT_NEAR(model->evaluate(on(2.0), false).predictions[0][0], std::asinh(2.0), 1e-9);
}

// The residual f - k u - (r(u) - k u) with k = 1e10 and r(u) = u + u^3 = f = pi: the two terms
// are 1e10 x the load, so the computed residual is a multiple of their rounding step (2^-19 at
// 1.2e10, 1.9e-6), and pi is 6.3e-7 from the nearest multiple: it can never reach 1e-10 of the
// load, nor 0. Newton must stop at that rounding floor as converged (within 1e-14 of |k u|), not
// spend its iterations and load steps on it; the solution is then as exact as the floor allows
// (|r| <= 1e-14 x 1.2e10, u to within that over the tangent 5.4: 2.3e-5).
TEST(IdentifyNonlinearSteps, ForcesFarAboveTheLoadConvergeAtTheirRoundingFloor) {
  const auto counts = std::make_shared<Counts>();
  const double k = 1e10, load = std::numbers::pi;
  const double q = load / 2, d = std::sqrt(q * q + 1.0 / 27);
  const double exact = std::cbrt(q + d) + std::cbrt(q - d);  // u + u^3 = load (Cardano)
  ASSERT_NEAR(cubic(exact), load, 1e-12);
  const double u =
      one_dof(cubic, cubic_tangent, counts, k)->evaluate(on(load), false).predictions[0][0];
  EXPECT_NEAR(u, exact, 1e-14 * k * exact / cubic_tangent(exact));
  EXPECT_EQ(counts->at_rest.load(), 1);  // no load steps
  // One attempt: from rest, the linear solution (u = load / k, far below the root), then Newton
  // and chord steps to the floor; measured 14 residuals and 5 tangents (the limit is 31 and 30).
  EXPECT_LE(counts->residuals.load(), 14);
  EXPECT_LE(counts->tangents.load(), 5);
}

// The same rounding floor ends a model's first solve on another model's kept tangent (the chord
// steps from that model's solution, as the large-deformation candidate's score test after the
// first round and a hold-out refit start). Model A, the spring above, converges with its
// Jacobian, so its tangent at the root is factorised and kept in the shared cache; model B, the
// same spring on that cache at a load 1e-3 larger, starts from A's root on A's tangent. The
// tangent is 1 + 3 u^2 = 5.4 there and moves by 6 u du ~ 1e-3 of it, so one chord step brings
// the residual from 3e-3 to about 3e-6, below the floor 1e-14 |k u| = 1.2e-4: B converges in its
// chord steps (2 residuals) and Newton's check of the start (1 more), without a tangent of its
// own or an attempt from rest. With the force tolerance alone in the chord steps (as before the
// one shared test) they ran to their stall limit before Newton accepted the iterate: 7 residuals.
TEST(IdentifyNonlinearSteps, AFirstSolveOnAKeptTangentConvergesAtTheRoundingFloor) {
  const auto counts = std::make_shared<Counts>();
  const auto cache = make_factorization_cache();
  const double k = 1e10, load = std::numbers::pi;
  const auto model_a = one_dof(cubic, cubic_tangent, counts, k, cache);
  (void)model_a->evaluate(on(load), true);  // keeps A's root and its tangent in the cache
  ASSERT_GE(counts->tangents.load(), 1);
  counts->reset();
  const double load_b = load * (1.0 + 1e-3);
  const double q = load_b / 2, d = std::sqrt(q * q + 1.0 / 27);
  const double exact = std::cbrt(q + d) + std::cbrt(q - d);
  ASSERT_NEAR(cubic(exact), load_b, 1e-12);
  const double u = one_dof(cubic, cubic_tangent, counts, k, cache)
                       ->evaluate(on(load_b), false)
                       .predictions[0][0];
  EXPECT_NEAR(u, exact, 1e-14 * k * exact / cubic_tangent(exact));
  EXPECT_EQ(counts->at_rest.load(), 0);
  EXPECT_EQ(counts->tangents.load(), 0);
  EXPECT_EQ(counts->residuals.load(), 3);
}

}  // namespace
}  // namespace isospring::fitting
