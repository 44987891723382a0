// The identification's building blocks against independent references: the Lame-split stiffness
// against analysis::assemble_stiffness, the forward model's analytic Jacobian against central
// differences, the nominal model against analysis::solve_static, the F-test against tables.
#include <gtest/gtest.h>

#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/constraints.hpp"
#include "isospring/analysis/elasticity.hpp"
#include "isospring/analysis/static_solver.hpp"
#include "isospring/fitting/identify.hpp"
#include "isospring/fitting/identify_assembly.hpp"
#include "isospring/fitting/identify_model.hpp"
#include "test_identify_plate.hpp"

namespace isospring::fitting {
namespace {

using testing::grid_markers;
using testing::plate_problem;

TEST(IdentifyAssembly, LameSplitReproducesTheAnalysisStiffness) {
  for (auto formulation :
       {analysis::Formulation::kPlaneStress, analysis::Formulation::kPlaneStrain}) {
    analysis::Problem problem = plate_problem(5, 3);
    problem.formulation = formulation;
    const analysis::DofMap dofs(problem);
    const LameMatrices parts = assemble_lame_stiffness(problem, dofs);
    const auto lame = analysis::lame_parameters(problem.material, formulation);
    const Eigen::SparseMatrix<double> upper = analysis::assemble_stiffness(problem, dofs);
    const Eigen::MatrixXd reference =
        Eigen::MatrixXd(Eigen::SparseMatrix<double>(upper.selfadjointView<Eigen::Upper>()));
    const Eigen::MatrixXd ours =
        Eigen::MatrixXd(lame.lambda * parts.lambda_part + lame.mu * parts.mu_part);
    // Same quadrature, different code: agreement to rounding.
    EXPECT_LT((ours - reference).norm(), 1e-12 * reference.norm());
  }
}

TEST(IdentifyAssembly, SideSpringsIntegrateTheSideLength) {
  // Normal + tangential = int R_a R_b I; summed over all DOFs of one component it is the side's
  // length times the thickness (partition of unity), and the normal part of side u0 (normal -x)
  // lives in the x components only.
  const analysis::Problem problem = plate_problem(5, 3);
  const analysis::DofMap dofs(problem);
  const SideSpringMatrices springs =
      assemble_side_springs(problem, dofs, analysis::parse_side("u0"));
  const Eigen::MatrixXd n = Eigen::MatrixXd(springs.normal);
  const Eigen::MatrixXd t = Eigen::MatrixXd(springs.tangential);
  EXPECT_NEAR(n.sum() + t.sum(), 2 * 0.04 * 0.005, 1e-15);
  double normal_x = 0.0;
  for (int r = 0; r < n.rows(); r += 2)
    for (int c = 0; c < n.cols(); c += 2) normal_x += n(r, c);
  EXPECT_NEAR(normal_x, 0.04 * 0.005, 1e-15);
  EXPECT_NEAR(n.sum(), 0.04 * 0.005, 1e-15);
}

TEST(IdentifyModel, NominalModelMatchesTheStaticSolver) {
  const analysis::Problem problem = plate_problem();
  std::vector<Marker> markers = grid_markers(problem);
  const PlacementResult placed = place_markers(problem.patches, markers, 1e-9);
  ASSERT_TRUE(placed.outside.empty());
  const auto ours = simulate_markers(problem, markers, placed.placements, {});
  const analysis::StaticResult reference = analysis::solve_static(problem);
  double scale = 0.0, worst = 0.0;
  for (size_t m = 0; m < markers.size(); ++m) {
    const int l = markers[m].load_case == "L1" ? 0 : 1;
    const nurbs::RationalBasis basis = problem.patches[0].basis(placed.placements[m].param, 0);
    Eigen::Vector3d u = Eigen::Vector3d::Zero();
    for (size_t a = 0; a < basis.indices.size(); ++a)
      u += basis.values[static_cast<Eigen::Index>(a)] *
           reference.load_cases[static_cast<size_t>(l)]
               .control_displacements[0][static_cast<size_t>(basis.indices[a])];
    worst = std::max(worst, (u - ours[m]).norm());
    scale = std::max(scale, u.norm());
  }
  EXPECT_GT(scale, 1e-5);
  EXPECT_LT(worst, 1e-10 * scale);
}

// The observation operator of the first load case's 18 markers of grid_markers(problem, 6, 3)
// (2D: 36 rows).
Observation first_case_observation(const analysis::Problem& problem, const analysis::DofMap& dofs) {
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
  Observation obs;
  obs.operator_.resize(36, dofs.num_dofs());
  obs.operator_.setFromTriplets(triplets.begin(), triplets.end());
  return obs;
}

TEST(IdentifyModel, AnalyticJacobianMatchesCentralDifferences) {
  // K = t0 (lambda K_l + mu K_mu) + t0 t1 K_grad + exp(t2) k K_springs with the clamped side
  // released, f = f_1 + t3 f_g, y = H u + t4 g: every kind of term with a nonlinear coefficient.
  const analysis::Problem problem = plate_problem(6, 3);
  const analysis::DofMap dofs(problem);
  const auto lame = analysis::lame_parameters(problem.material, problem.formulation);
  const LameMatrices parts = assemble_lame_stiffness(problem, dofs);
  const LameMatrices gradient = assemble_lame_stiffness(
      problem, dofs, [](const Eigen::Vector3d& x) { return (x.x() - 0.05) / 0.1; });
  const SideSpringMatrices springs =
      assemble_side_springs(problem, dofs, analysis::parse_side("u0"));
  ModelTerms terms;
  terms.num_parameters = 5;
  terms.stiffness.push_back({parts.lambda_part, linear_coefficient(0, lame.lambda)});
  terms.stiffness.push_back({parts.mu_part, linear_coefficient(0, lame.mu)});
  terms.stiffness.push_back({lame.lambda * gradient.lambda_part + lame.mu * gradient.mu_part,
                             product(linear_coefficient(0), linear_coefficient(1))});
  const double k_ref = 1e6 / 0.1;
  terms.stiffness.push_back(
      {springs.normal + springs.tangential, [k_ref](const Eigen::VectorXd& t, Eigen::VectorXd* g) {
         if (g) {
           g->setZero(t.size());
           (*g)[2] = k_ref * std::exp(t[2]);
         }
         return k_ref * std::exp(t[2]);
       }});
  analysis::LoadCase gravity;
  gravity.gravity.y() = 1.0;
  terms.loads.push_back({0, analysis::assemble_load(problem, dofs, problem.load_cases[0]),
                         constant_coefficient(1.0)});
  terms.loads.push_back(
      {-1, analysis::assemble_load(problem, dofs, gravity), linear_coefficient(3)});
  const Observation obs = first_case_observation(problem, dofs);
  terms.offsets.push_back({0, Eigen::VectorXd::LinSpaced(36, -1.0, 1.0), linear_coefficient(4)});
  const analysis::Constraints constraints = analysis::build_constraints(problem, dofs);
  terms.released_dofs = constraints.dofs;
  const ForwardModel model(terms, {obs}, constraints.dofs, constraints.values, dofs.num_dofs(), 1);

  const Eigen::VectorXd theta = (Eigen::VectorXd(5) << 1.2, 0.3, 1.5, -9.0, 1e-5).finished();
  const ModelEvaluation eval = model.evaluate(theta, true);
  ASSERT_EQ(eval.jacobians[0].cols(), 5);
  for (int k = 0; k < 5; ++k) {
    const double h = 1e-5 * std::max(1.0, std::abs(theta[k]));
    Eigen::VectorXd up = theta, down = theta;
    up[k] += h;
    down[k] -= h;
    const Eigen::VectorXd difference =
        (model.evaluate(up, false).predictions[0] - model.evaluate(down, false).predictions[0]) /
        (2 * h);
    // Central differences are O(h^2) accurate: relative agreement to 1e-6 or better.
    EXPECT_GT(difference.norm(), 0.0) << k;
    EXPECT_LT((eval.jacobians[0].col(k) - difference).norm(), 1e-6 * difference.norm()) << k;
  }
}

// Support springs touch only the clamped side's DOFs: when only their stiffness changes (E and
// the rest scaled alike), the model solves by a low-rank (Woodbury) update of the cached
// factorisation. Its predictions and Jacobian must equal a fresh factorisation's to round-off,
// for springs 1000x softer and 1000x stiffer than the cached ones, and with E changed too.
TEST(IdentifyModel, LowRankSpringUpdatesMatchFreshFactorisations) {
  const analysis::Problem problem = plate_problem(12, 6);
  const analysis::DofMap dofs(problem);
  const auto lame = analysis::lame_parameters(problem.material, problem.formulation);
  const LameMatrices parts = assemble_lame_stiffness(problem, dofs);
  const SideSpringMatrices springs =
      assemble_side_springs(problem, dofs, analysis::parse_side("u0"));
  ModelTerms terms;
  terms.num_parameters = 3;
  terms.stiffness.push_back({parts.lambda_part, linear_coefficient(0, lame.lambda)});
  terms.stiffness.push_back({parts.mu_part, linear_coefficient(0, lame.mu)});
  const double k_ref = 1e6 / 0.1;
  for (int k : {1, 2})
    terms.stiffness.push_back({k == 1 ? springs.normal : springs.tangential,
                               [k_ref, k](const Eigen::VectorXd& t, Eigen::VectorXd* g) {
                                 if (g) {
                                   g->setZero(t.size());
                                   (*g)[k] = k_ref * std::exp(t[k]);
                                 }
                                 return k_ref * std::exp(t[k]);
                               }});
  terms.loads.push_back({0, analysis::assemble_load(problem, dofs, problem.load_cases[0]),
                         constant_coefficient(1.0)});
  const Observation obs = first_case_observation(problem, dofs);
  const analysis::Constraints constraints = analysis::build_constraints(problem, dofs);
  terms.released_dofs = constraints.dofs;
  const auto shared = make_factorization_cache();
  const ForwardModel updated(terms, {obs}, constraints.dofs, constraints.values, dofs.num_dofs(), 1,
                             shared);
  const Eigen::VectorXd start = Eigen::Vector3d(1.0, 0.5, 0.5);
  updated.evaluate(start, false);  // factorises; later evaluations may update it
  for (const Eigen::Vector3d& theta :
       {Eigen::Vector3d(1.0, 0.5 - 6.9, 0.5), Eigen::Vector3d(1.0, 0.5 + 6.9, 0.5 - 3.0),
        Eigen::Vector3d(1.7, 2.0, -1.0)}) {
    const ModelEvaluation low_rank = updated.evaluate(theta, true);
    const ForwardModel fresh(terms, {obs}, constraints.dofs, constraints.values, dofs.num_dofs(),
                             1);  // a cache of its own: factorises at theta
    const ModelEvaluation direct = fresh.evaluate(theta, true);
    const Eigen::VectorXd& y = direct.predictions[0];
    EXPECT_LT((low_rank.predictions[0] - y).norm(), 1e-9 * y.norm()) << theta.transpose();
    EXPECT_LT((low_rank.jacobians[0] - direct.jacobians[0]).norm(),
              1e-8 * direct.jacobians[0].norm())
        << theta.transpose();
  }
  // One factorisation for all of them: the rest were low-rank updates.
  const FactorizationStats stats = updated.factorization_stats();
  EXPECT_EQ(stats.factorizations, 1);
  EXPECT_EQ(stats.low_rank_updates, 3);
}

// K(theta) = lambda(E, nu) K_l + mu(E, nu) K_mu: every nu is a new factorisation, but K's pattern
// is the same, so CHOLMOD's symbolic analysis (the ordering) is made once and every later
// factorisation is numeric only. The results must equal a fresh model's at each theta.
TEST(IdentifyModel, RefactorisationsReuseOneSymbolicAnalysis) {
  const analysis::Problem problem = plate_problem(12, 6);
  const analysis::DofMap dofs(problem);
  const LameMatrices parts = assemble_lame_stiffness(problem, dofs);
  ModelTerms terms;
  terms.num_parameters = 2;  // E / E_prior, nu
  const double e_prior = problem.material.youngs_modulus;
  auto lame = [e_prior](bool lambda) -> Coefficient {
    return [e_prior, lambda](const Eigen::VectorXd& t, Eigen::VectorXd* g) {
      const double nu = t[1];
      const double per_e = lambda ? nu / (1.0 - nu * nu) : 0.5 / (1.0 + nu);
      const double d_nu = lambda ? (1.0 + nu * nu) / ((1.0 - nu * nu) * (1.0 - nu * nu))
                                 : -0.5 / ((1.0 + nu) * (1.0 + nu));
      if (g) *g = Eigen::Vector2d(e_prior * per_e, e_prior * t[0] * d_nu);
      return e_prior * t[0] * per_e;
    };
  };
  terms.stiffness.push_back({parts.lambda_part, lame(true)});
  terms.stiffness.push_back({parts.mu_part, lame(false)});
  terms.loads.push_back({0, analysis::assemble_load(problem, dofs, problem.load_cases[0]),
                         constant_coefficient(1.0)});
  const Observation obs = first_case_observation(problem, dofs);
  const analysis::Constraints constraints = analysis::build_constraints(problem, dofs);
  const ForwardModel model(terms, {obs}, constraints.dofs, constraints.values, dofs.num_dofs(), 1);
  for (const double nu : {0.3, 0.25, 0.35, 0.1}) {
    const Eigen::Vector2d theta(1.2, nu);
    const ModelEvaluation reused = model.evaluate(theta, true);
    const ForwardModel fresh(terms, {obs}, constraints.dofs, constraints.values, dofs.num_dofs(),
                             1);
    const ModelEvaluation direct = fresh.evaluate(theta, true);
    const Eigen::VectorXd& y = direct.predictions[0];
    EXPECT_LT((reused.predictions[0] - y).norm(), 1e-12 * y.norm()) << nu;
    EXPECT_LT((reused.jacobians[0] - direct.jacobians[0]).norm(),
              1e-12 * direct.jacobians[0].norm())
        << nu;
  }
  const FactorizationStats stats = model.factorization_stats();
  EXPECT_EQ(stats.factorizations, 4);
  EXPECT_EQ(stats.analyses, 1);
}

TEST(IdentifyStatistics, FTestMatchesTables) {
  // Upper 1% and 5% points of F (Abramowitz & Stegun table 26.9).
  EXPECT_NEAR(f_test_p_value(6.85, 1, 120), 0.01, 2e-4);
  EXPECT_NEAR(f_test_p_value(2.68, 3, 120), 0.05, 5e-4);
  EXPECT_NEAR(f_test_p_value(3.95, 3, 120), 0.01, 2e-4);
  EXPECT_EQ(f_test_p_value(0.0, 2, 10), 1.0);
}

TEST(IdentifyStatistics, NeighbourNoiseEstimateIgnoresSmoothFields) {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 1e-3);
  std::vector<Eigen::Vector3d> positions, residuals;
  for (int j = 0; j < 30; ++j)
    for (int i = 0; i < 30; ++i) {
      const Eigen::Vector3d x(i * 0.01, j * 0.01, 0.0);
      positions.push_back(x);
      // A smooth misfit 20x the noise and the noise.
      residuals.emplace_back(0.02 * std::sin(3 * x.x()) + noise(rng),
                             0.02 * x.y() * x.x() + noise(rng), 0.0);
    }
  const double sigma = estimate_noise(positions, residuals, std::vector<int>(900, 0), 2);
  // 1800 samples: the MAD has a relative standard error of about 1.1/sqrt(1800) = 2.6 %.
  EXPECT_NEAR(sigma, 1e-3, 0.1e-3);
}

// An unmodelled effect whose misfit changes by several noise levels between neighbouring
// markers (the suite's tube with undeclared self-weight: neighbour differences gave 2.7 x the
// true noise): the local linear fits remove the gradient exactly and leave the curvature across
// a neighbourhood (radius about 0.01 m), here below 5e-7 m, 0.05 x the noise.
TEST(IdentifyStatistics, NoiseEstimateIgnoresSteepSmoothMisfits) {
  std::mt19937 rng(11);
  const double sigma = 1e-5;
  std::normal_distribution<double> noise(0.0, sigma);
  std::vector<Eigen::Vector3d> positions, residuals;
  std::vector<int> group;
  for (int load_case = 0; load_case < 2; ++load_case)
    for (int j = 0; j < 25; ++j)
      for (int i = 0; i < 40; ++i) {
        // Markers on two faces of a bar (z = 0 and y = 0): the fits must handle coplanar points.
        const Eigen::Vector3d x = j < 12 ? Eigen::Vector3d(i * 0.005, j * 0.005, 0.0)
                                         : Eigen::Vector3d(i * 0.005, 0.0, (j - 12) * 0.005);
        positions.push_back(x);
        group.push_back(load_case);
        // Steps of 5e-5 m between neighbours (5 x the noise) and a quadratic misfit.
        const double smooth = 1e-2 * x.x() + 2e-3 * x.x() * x.x() + 4e-3 * x.y() * x.z();
        residuals.emplace_back(smooth + noise(rng), -smooth + noise(rng),
                               0.5 * smooth + noise(rng));
      }
  const double estimate = estimate_noise(positions, residuals, group, 3);
  EXPECT_NEAR(estimate, sigma, 0.1 * sigma);
  // Plain neighbour differences would see the gradient: |r_m - r_nn| is 5e-5 m + noise.
  double step = 0.0;
  for (int c = 0; c < 3; ++c) step = std::max(step, std::abs(residuals[1][c] - residuals[0][c]));
  EXPECT_GT(step, 3.0 * sigma);
}

TEST(IdentifyStatistics, NoiseEstimateNeedsEnoughNeighbours) {
  // Three markers in a load case leave no residual degrees of freedom for a linear fit.
  const std::vector<Eigen::Vector3d> positions{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const std::vector<Eigen::Vector3d> residuals{{1, 2, 0}, {3, 1, 0}, {0, 0, 0}};
  EXPECT_EQ(estimate_noise(positions, residuals, {0, 0, 0}, 2), 0.0);
}

TEST(MeasurePlacement, FindsParametersAndFlagsMarkersOffTheModel) {
  const analysis::Problem problem = plate_problem(4, 2);
  std::vector<Marker> markers(3);
  markers[0].position = Eigen::Vector3d(0.025, 0.01, 0.0);
  markers[1].position = Eigen::Vector3d(0.11, 0.02, 0.0);   // 1 cm right of the plate
  markers[2].position = Eigen::Vector3d(0.025, 0.01, 0.0);  // same point: placed once
  const PlacementResult placed = place_markers(problem.patches, markers, 1e-6);
  ASSERT_EQ(placed.outside.size(), 1u);
  EXPECT_EQ(placed.outside[0], 1);
  EXPECT_NEAR(placed.placements[1].distance, 0.01, 1e-9);
  // The parametrisation is linear: u = x / 0.1, v = y / 0.04.
  EXPECT_NEAR(placed.placements[0].param[0], 0.25, 1e-10);
  EXPECT_NEAR(placed.placements[0].param[1], 0.25, 1e-10);
  EXPECT_LT(placed.placements[0].distance, 1e-12);
}

}  // namespace
}  // namespace isospring::fitting
