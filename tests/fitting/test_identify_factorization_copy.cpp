// A copy of a forward model's factorisation cache (copy_factorization_cache, what the hold-out
// folds start from): a model with the same stiffness solves on the copy without factorising, with
// the numbers of the original cache, and the two caches are independent afterwards.
#include <gtest/gtest.h>

#include <cmath>

#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/constraints.hpp"
#include "isospring/analysis/elasticity.hpp"
#include "isospring/fitting/identify.hpp"
#include "isospring/fitting/identify_assembly.hpp"
#include "isospring/fitting/identify_model.hpp"
#include "test_identify_plate.hpp"

namespace isospring::fitting {
namespace {

using testing::grid_markers;
using testing::plate_problem;

// The plate with springs on its clamped side (a local term: solves through the low-rank update
// once only the springs change) and E as parameters: theta = (E / E_prior, log spring scale).
struct SpringPlate {
  analysis::Problem problem = plate_problem(12, 6);
  analysis::DofMap dofs{problem};
  analysis::Constraints constraints = analysis::build_constraints(problem, dofs);
  ModelTerms terms;
  Observation observation;

  SpringPlate() {
    const auto lame = analysis::lame_parameters(problem.material, problem.formulation);
    const LameMatrices parts = assemble_lame_stiffness(problem, dofs);
    const SideSpringMatrices springs =
        assemble_side_springs(problem, dofs, analysis::parse_side("u0"));
    terms.num_parameters = 2;
    terms.stiffness.push_back({parts.lambda_part, linear_coefficient(0, lame.lambda)});
    terms.stiffness.push_back({parts.mu_part, linear_coefficient(0, lame.mu)});
    const double k_ref = 1e6 / 0.1;
    terms.stiffness.push_back({springs.normal + springs.tangential,
                               [k_ref](const Eigen::VectorXd& t, Eigen::VectorXd* g) {
                                 if (g) {
                                   g->setZero(t.size());
                                   (*g)[1] = k_ref * std::exp(t[1]);
                                 }
                                 return k_ref * std::exp(t[1]);
                               }});
    terms.loads.push_back({0, analysis::assemble_load(problem, dofs, problem.load_cases[0]),
                           constant_coefficient(1.0)});
    terms.released_dofs = constraints.dofs;
    const std::vector<Marker> markers = grid_markers(problem, 6, 3);
    const PlacementResult placed = place_markers(problem.patches, markers, 1e-9);
    std::vector<Eigen::Triplet<double>> triplets;
    for (int m = 0; m < 18; ++m) {
      const nurbs::RationalBasis basis =
          problem.patches[0].basis(placed.placements[static_cast<size_t>(m)].param, 0);
      for (int c = 0; c < 2; ++c)
        for (size_t a = 0; a < basis.indices.size(); ++a)
          triplets.emplace_back(2 * m + c, dofs.dof(0, basis.indices[a], c),
                                basis.values[static_cast<Eigen::Index>(a)]);
    }
    observation.operator_.resize(36, dofs.num_dofs());
    observation.operator_.setFromTriplets(triplets.begin(), triplets.end());
  }

  ForwardModel model(std::shared_ptr<FactorizationCache> cache) const {
    return ForwardModel(terms, {observation}, constraints.dofs, constraints.values, dofs.num_dofs(),
                        1, std::move(cache));
  }
};

TEST(IdentifyFactorizationCopy, ACopiedFactorSolvesLikeTheOriginalWithoutFactorising) {
  const SpringPlate plate;
  const auto original = make_factorization_cache();
  const ForwardModel first = plate.model(original);
  const Eigen::Vector2d start(1.0, 0.0);
  first.evaluate(start, true);                      // factorises
  first.evaluate(Eigen::Vector2d(1.0, 2.0), true);  // low rank: W and G made
  const auto copy = copy_factorization_cache(*original);
  const ForwardModel second = plate.model(copy);
  // Every term scaled by 1.3 (the factor as it is), and the springs changed alone (a low-rank
  // update on the copied W).
  for (const Eigen::Vector2d& theta :
       {Eigen::Vector2d(1.3, std::log(1.3)), Eigen::Vector2d(0.8, -3.0)}) {
    const ModelEvaluation on_copy = second.evaluate(theta, true);
    const ModelEvaluation on_original = first.evaluate(theta, true);
    // Same factor, same W, same arithmetic: the same numbers to the last bit.
    EXPECT_EQ(on_copy.predictions[0], on_original.predictions[0]) << theta.transpose();
    EXPECT_EQ(on_copy.jacobians[0], on_original.jacobians[0]) << theta.transpose();
    // And a fresh factorisation's to round-off.
    const ModelEvaluation fresh = plate.model(nullptr).evaluate(theta, true);
    EXPECT_LT((on_copy.predictions[0] - fresh.predictions[0]).norm(),
              1e-9 * fresh.predictions[0].norm());
  }
  const FactorizationStats stats = second.factorization_stats();
  EXPECT_EQ(stats.factorizations, 0);
  EXPECT_EQ(stats.analyses, 0);
  EXPECT_EQ(stats.reuses, 1);
  EXPECT_EQ(stats.low_rank_updates, 1);
}

TEST(IdentifyFactorizationCopy, CopyAndOriginalAreIndependent) {
  const SpringPlate plate;
  const auto original = make_factorization_cache();
  const ForwardModel first = plate.model(original);
  const Eigen::Vector2d start(1.0, 0.0);
  const ModelEvaluation before = first.evaluate(start, false);
  const auto copy = copy_factorization_cache(*original);
  // The copy moves to another K (E doubled, springs 1e4 x softer): whether it updates or
  // refactorises, the original must not notice.
  const ForwardModel second = plate.model(copy);
  const Eigen::Vector2d elsewhere(2.0, -9.2);
  const ModelEvaluation moved = second.evaluate(elsewhere, false);
  const ModelEvaluation fresh = plate.model(nullptr).evaluate(elsewhere, false);
  EXPECT_LT((moved.predictions[0] - fresh.predictions[0]).norm(),
            1e-9 * fresh.predictions[0].norm());
  const long factorised = first.factorization_stats().factorizations;
  const ModelEvaluation again = first.evaluate(start, false);
  EXPECT_EQ(again.predictions[0], before.predictions[0]);
  EXPECT_EQ(first.factorization_stats().factorizations, factorised);
  // A cache without a factorisation copies to an empty one, which factorises on first use.
  const auto empty = copy_factorization_cache(*make_factorization_cache());
  const ForwardModel third = plate.model(empty);
  third.evaluate(start, false);
  EXPECT_EQ(third.factorization_stats().factorizations, 1);
}

}  // namespace
}  // namespace isospring::fitting
