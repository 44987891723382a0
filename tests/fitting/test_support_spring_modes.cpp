// The support springs' split into axial, rocking and the rest (support_spring_modes.hpp) against
// closed forms: a rigid block on a Winkler layer (axial stiffness k_a A, rocking stiffness k_n I
// about each centroidal axis of the side), the split's identities (the parts sum to the normal
// springs, each is positive semi-definite, the rest does not see rigid motions), and the forward
// model's low-rank update with the split springs against a fresh factorisation.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/constraints.hpp"
#include "isospring/analysis/elasticity.hpp"
#include "isospring/analysis/sides.hpp"
#include "isospring/fitting/identify_assembly.hpp"
#include "isospring/fitting/identify_model.hpp"
#include "isospring/fitting/support_spring_modes.hpp"
#include "isospring/nurbs/refine.hpp"
#include "test_identify_plate.hpp"

namespace isospring::fitting {
namespace {

// A 0.1 x 0.03 x 0.02 m block away from the origin (the centroid of its side x = x0 is not at
// zero), degree 2, 3 x 3 x 2 elements, clamped at x = x0 (side u0); a pull and a bending load.
const Eigen::Vector3d kCorner(0.2, -0.01, 0.05);
const Eigen::Vector3d kSize(0.1, 0.03, 0.02);

analysis::Problem block_problem(std::array<int, 3> elements = {3, 3, 2}) {
  const nurbs::KnotVector linear(1, {0, 0, 1, 1});
  std::vector<Eigen::Vector3d> points;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i)
        points.push_back(kCorner + Eigen::Vector3d(i, j, k).cwiseProduct(kSize));
  analysis::Problem problem;
  problem.formulation = analysis::Formulation::kSolid;
  problem.material = {1e7, 0.45, 1000, 1.0};
  problem.patches.push_back(
      nurbs::k_refine(nurbs::Patch({linear, linear, linear}, points), {2, 2, 2}, elements));
  analysis::Support clamp;
  clamp.side = {0, 0, 0};
  clamp.fixed = {true, true, true};
  problem.supports.push_back(clamp);
  for (const auto& [id, traction] : std::vector<std::pair<std::string, Eigen::Vector3d>>{
           {"pull", {2e4, 0, 0}}, {"down", {0, 0, -2e3}}}) {
    analysis::LoadCase load;
    load.id = id;
    load.tractions.push_back({{0, 0, 1}, traction, {}});
    problem.load_cases.push_back(load);
  }
  return problem;
}

// DOF vector of u(x) = field(x) at every control point (exact for fields linear in x).
template <typename Field>
Eigen::VectorXd interpolate(const analysis::Problem& problem, const analysis::DofMap& dofs,
                            Field field) {
  Eigen::VectorXd v = Eigen::VectorXd::Zero(dofs.num_dofs());
  const nurbs::Patch& patch = problem.patches[0];
  for (int a = 0; a < static_cast<int>(patch.control_points().size()); ++a) {
    const Eigen::Vector3d u = field(patch.control_point(a));
    for (int c = 0; c < dofs.dofs_per_node(); ++c) v[dofs.dof(0, a, c)] = u[c];
  }
  return v;
}

double energy(const Eigen::SparseMatrix<double>& m, const Eigen::VectorXd& u) {
  return u.dot(m * u);
}

TEST(SupportSpringModes, RigidBlockOnAWinklerLayer) {
  // Side x = x0 of the block, area A = Ly Lz, second moments about its centroidal axes
  // I_z = Lz Ly^3 / 12 (tilt along y) and I_y = Ly Lz^3 / 12 (tilt along z). A rigid motion of
  // the block with normal displacement w0 + a (y - yc) + b (z - zc) stores
  // (k_a A w0^2 + k_n (I_z a^2 + I_y b^2)) / 2 in springs k_a axial + k_n (rocking + rest):
  // axial stiffness k_a A, rocking stiffnesses k_n I. Tangential components do not count.
  const analysis::Problem problem = block_problem();
  const analysis::DofMap dofs(problem);
  const analysis::Side side = analysis::parse_side("u0");
  const SideSpringMatrices springs = assemble_side_springs(problem, dofs, side);
  const NormalSpringSplit split = split_normal_springs(problem, dofs, side, springs.normal);
  const double ly = kSize.y(), lz = kSize.z(), area = ly * lz;
  const double iz = lz * ly * ly * ly / 12, iy = ly * lz * lz * lz / 12;
  const Eigen::Vector3d centre = kCorner + 0.5 * kSize;
  const double w0 = 3e-5, a = 2e-3, b = -5e-3;
  const Eigen::VectorXd u = interpolate(problem, dofs, [&](const Eigen::Vector3d& x) {
    return Eigen::Vector3d(w0 + a * (x.y() - centre.y()) + b * (x.z() - centre.z()), 7e-6 * x.z(),
                           -4e-6);
  });
  // Exact quadrature of polynomials: agreement to rounding.
  EXPECT_NEAR(energy(split.axial, u), area * w0 * w0, 1e-12 * area * w0 * w0);
  const double rocking = iz * a * a + iy * b * b;
  EXPECT_NEAR(energy(split.rocking, u), rocking, 1e-12 * rocking);
  EXPECT_NEAR(energy(split.rest, u), 0.0, 1e-12 * energy(springs.normal, u));
  const double k_a = 4e9, k_n = 8e8;
  const Eigen::SparseMatrix<double> k =
      k_a * split.axial + k_n * (Eigen::SparseMatrix<double>(split.rocking + split.rest));
  EXPECT_NEAR(energy(k, u), k_a * area * w0 * w0 + k_n * rocking,
              1e-12 * (k_a * area * w0 * w0 + k_n * rocking));
  // The axial part alone: the resultant normal force of a uniform push is k_a A w0.
  const Eigen::VectorXd push =
      interpolate(problem, dofs, [&](const Eigen::Vector3d&) { return Eigen::Vector3d(w0, 0, 0); });
  const Eigen::VectorXd unit_x =
      interpolate(problem, dofs, [&](const Eigen::Vector3d&) { return Eigen::Vector3d(1, 0, 0); });
  EXPECT_NEAR(unit_x.dot(k * push), k_a * area * w0, 1e-12 * k_a * area * w0);
}

TEST(SupportSpringModes, PartsSumToTheNormalSpringsAndArePositiveSemiDefinite) {
  for (const bool plane : {false, true}) {
    const analysis::Problem problem = plane ? testing::plate_problem(5, 3) : block_problem();
    const analysis::DofMap dofs(problem);
    const analysis::Side side = analysis::parse_side("u0");
    const SideSpringMatrices springs = assemble_side_springs(problem, dofs, side);
    const NormalSpringSplit split = split_normal_springs(problem, dofs, side, springs.normal);
    const Eigen::MatrixXd normal(springs.normal);
    const double scale = normal.norm();
    EXPECT_LT((Eigen::MatrixXd(split.axial) + Eigen::MatrixXd(split.rocking) +
               Eigen::MatrixXd(split.rest) - normal)
                  .norm(),
              1e-14 * scale);
    for (const Eigen::SparseMatrix<double>* part : {&split.axial, &split.rocking, &split.rest}) {
      const Eigen::MatrixXd m(*part);
      EXPECT_LT((m - m.transpose()).norm(), 1e-15 * scale);
      const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(m);
      EXPECT_GT(eig.eigenvalues().minCoeff(), -1e-13 * scale) << plane;
      EXPECT_GT(eig.eigenvalues().maxCoeff(), 1e-3 * scale) << plane;  // not empty
    }
    // Ranks: one axial direction; two rotations about the side's in-plane axes in 3D, one (about
    // the out-of-plane axis) in 2D.
    const auto rank = [&](const Eigen::SparseMatrix<double>& m) {
      const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig{Eigen::MatrixXd(m)};
      return (eig.eigenvalues().array() > 1e-10 * scale).count();
    };
    EXPECT_EQ(rank(split.axial), 1);
    EXPECT_EQ(rank(split.rocking), plane ? 1 : 2);
    // The rest does not see rigid motions: translations and small rotations about any point.
    std::mt19937 rng(5);
    std::normal_distribution<double> normal_draw(0.0, 1.0);
    for (int trial = 0; trial < 4; ++trial) {
      const Eigen::Vector3d t(normal_draw(rng), normal_draw(rng), plane ? 0 : normal_draw(rng));
      const Eigen::Vector3d w =
          plane ? Eigen::Vector3d(0, 0, normal_draw(rng))
                : Eigen::Vector3d(normal_draw(rng), normal_draw(rng), normal_draw(rng));
      const Eigen::Vector3d p(normal_draw(rng), normal_draw(rng), 0.0);
      const Eigen::VectorXd rigid = interpolate(problem, dofs, [&](const Eigen::Vector3d& x) {
        return Eigen::Vector3d(t + w.cross(x - p));
      });
      EXPECT_LT(std::abs(energy(split.rest, rigid)), 1e-12 * energy(springs.normal, rigid));
    }
  }
}

// The split springs are local terms of the forward model (the clamped side's DOFs): a change of
// k_n, k_t or k_a / k_n solves by a low-rank update of the cached factorisation. Predictions and
// Jacobians must equal a fresh factorisation's, from k_a = k_n to k_a = 10 k_n (the bounds of
// support_compliance), with k_n from e^-1 to e^3 k_ref.
TEST(SupportSpringModes, LowRankUpdateEqualsARefactorisedSolve) {
  const analysis::Problem problem = block_problem({6, 3, 2});
  const analysis::DofMap dofs(problem);
  const auto lame = analysis::lame_parameters(problem.material, problem.formulation);
  const LameMatrices parts = assemble_lame_stiffness(problem, dofs);
  const analysis::Side side = analysis::parse_side("u0");
  const SideSpringMatrices springs = assemble_side_springs(problem, dofs, side);
  const NormalSpringSplit split = split_normal_springs(problem, dofs, side, springs.normal);
  ModelTerms terms;
  terms.num_parameters = 4;
  terms.stiffness.push_back({parts.lambda_part, linear_coefficient(0, lame.lambda)});
  terms.stiffness.push_back({parts.mu_part, linear_coefficient(0, lame.mu)});
  const double k_ref = problem.material.youngs_modulus / kSize.x();
  // support_compliance's parameterisation: k_n = k_ref exp(t1) on rocking and the rest,
  // k_t = k_ref exp(t2), k_a = k_n exp(t3) on the axial part.
  const std::vector<Eigen::SparseMatrix<double>> spring_terms{split.rocking + split.rest,
                                                              springs.tangential, split.axial};
  const std::vector<std::vector<int>> exponents{{1}, {2}, {1, 3}};
  for (size_t k = 0; k < 3; ++k)
    terms.stiffness.push_back({spring_terms[k], [k_ref, indices = exponents[k]](
                                                    const Eigen::VectorXd& t, Eigen::VectorXd* g) {
                                 double exponent = 0.0;
                                 for (int i : indices) exponent += t[i];
                                 if (g) {
                                   g->setZero(t.size());
                                   for (int i : indices) (*g)[i] = k_ref * std::exp(exponent);
                                 }
                                 return k_ref * std::exp(exponent);
                               }});
  std::vector<Observation> observations;
  for (const analysis::LoadCase& load : problem.load_cases) {
    terms.loads.push_back({static_cast<int>(observations.size()),
                           analysis::assemble_load(problem, dofs, load),
                           constant_coefficient(1.0)});
    // Observe every x and z component of the free end's control points.
    Observation obs;
    const std::vector<int> end = analysis::side_control_points(problem.patches[0], 0, 1);
    std::vector<Eigen::Triplet<double>> triplets;
    for (size_t m = 0; m < end.size(); ++m) {
      triplets.emplace_back(static_cast<int>(2 * m), dofs.dof(0, end[m], 0), 1.0);
      triplets.emplace_back(static_cast<int>(2 * m + 1), dofs.dof(0, end[m], 2), 1.0);
    }
    obs.operator_.resize(static_cast<Eigen::Index>(2 * end.size()), dofs.num_dofs());
    obs.operator_.setFromTriplets(triplets.begin(), triplets.end());
    observations.push_back(obs);
  }
  const analysis::Constraints constraints = analysis::build_constraints(problem, dofs);
  terms.released_dofs = constraints.dofs;
  const auto shared = make_factorization_cache();
  const int cases = static_cast<int>(observations.size());
  const ForwardModel updated(terms, observations, constraints.dofs, constraints.values,
                             dofs.num_dofs(), cases, shared);
  const Eigen::Vector4d start(1.0, 1.0, 1.0, 1.0);
  updated.evaluate(start, false);  // factorises; later evaluations may update it
  const long before = factorization_stats(*shared).low_rank_updates;
  for (const Eigen::Vector4d& theta :
       {Eigen::Vector4d(1.0, 1.0, 1.0, std::log(10.0)), Eigen::Vector4d(1.0, 1.0 - 2.0, 1.5, 0.0),
        Eigen::Vector4d(1.0, 3.0, -1.0, 1.2)}) {
    const ModelEvaluation low_rank = updated.evaluate(theta, true);
    const ForwardModel fresh(terms, observations, constraints.dofs, constraints.values,
                             dofs.num_dofs(), cases);  // a cache of its own: factorises at theta
    const ModelEvaluation direct = fresh.evaluate(theta, true);
    for (int l = 0; l < cases; ++l) {
      const Eigen::VectorXd& y = direct.predictions[static_cast<size_t>(l)];
      EXPECT_LT((low_rank.predictions[static_cast<size_t>(l)] - y).norm(), 1e-9 * y.norm())
          << theta.transpose();
      const Eigen::MatrixXd& j = direct.jacobians[static_cast<size_t>(l)];
      EXPECT_LT((low_rank.jacobians[static_cast<size_t>(l)] - j).norm(), 1e-8 * j.norm())
          << theta.transpose();
    }
  }
  EXPECT_EQ(factorization_stats(*shared).low_rank_updates - before,
            3);  // none of them refactorised
  // The axial springs change the pull, not only the bending: k_a is seen by the data.
  const ModelEvaluation soft = updated.evaluate(Eigen::Vector4d(1.0, 1.0, 1.0, 0.0), false);
  const ModelEvaluation stiff =
      updated.evaluate(Eigen::Vector4d(1.0, 1.0, 1.0, std::log(10.0)), false);
  EXPECT_GT((soft.predictions[0] - stiff.predictions[0]).norm(),
            1e-2 * stiff.predictions[0].norm());
}

}  // namespace
}  // namespace isospring::fitting
