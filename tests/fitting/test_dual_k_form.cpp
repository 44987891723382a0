// The K form of the per-spring dual Levenberg-Marquardt system (a I + J W J^T = K^-1 (a K^2 + G)
// K^-1 when one load case observes every free DOF): checked against the two other ways of forming
// it, the adjoint Gram matrix (gram()) and the dense product of the Jacobian with itself. These
// are internals of the fitting module, so the test includes its private headers.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <random>

#include "../../fitting/src/nmsm/displacement_model.hpp"
#include "../../fitting/src/nmsm/dual_levenberg_marquardt.hpp"
#include "isospring/analysis/spring_static.hpp"
#include "isospring/fitting/spring_mesh.hpp"
#include "nmsm_test_models.hpp"

namespace isospring::fitting {
namespace {

// 3x3x3 box net, side u0 fixed, one load case on the far side (every node observed).
DisplacementFitData one_case_data() {
  const analysis::Problem problem = testing::grid_problem({3, 3, 3}, {2.0, 2.0, 2.0});
  SpringMesh mesh = build_spring_mesh(problem);
  const nurbs::Patch& patch = problem.patches[0];
  for (int cp = 0; cp < patch.num_points(); ++cp)
    mesh.network.fixed[cp] = patch.net_position(cp)[0] == 0;
  DisplacementFitData data;
  data.network = mesh.network;
  data.particle_of_node = particle_of_node(problem, mesh);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(patch.num_points()) * 3);
  for (int cp = 0; cp < patch.num_points(); ++cp)
    if (patch.net_position(cp)[0] == patch.num_points(0) - 1)
      f.segment(cp * 3, 3) = Eigen::Vector3d(1, -1, 0.5) * 10.0;
  analysis::SpringNetwork truth = mesh.network;
  for (size_t s = 0; s < truth.springs.size(); ++s)
    truth.springs[s].stiffness = 1000.0 * (1.0 + 0.5 * static_cast<double>(s % 3));
  data.loads.push_back(f);
  data.references.push_back(analysis::solve_spring_linear(truth, f).displacement);
  return data;
}

Eigen::VectorXd random_log_stiffness(int springs) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> log_k(std::log(500.0), std::log(5000.0));
  Eigen::VectorXd theta(springs);
  for (auto& t : theta) t = log_k(rng);
  return theta;
}

// Relative agreement 1e-12: the three forms differ only by round-off (measured ~2e-15 here),
// amplified by the conditioning of K (entering squared in a K^2 + G); a wrong term (a missing
// K, a permuted row, a wrong weight or prior term) is O(1).
TEST(DualKForm, SystemEqualsTheAdjointGramAndTheDenseProduct) {
  const DisplacementFitData data = one_case_data();
  const Grouping grouping = one_group_per_spring(data.network);
  detail::DisplacementModel model(data, grouping);
  const int p = grouping.num_groups();
  Eigen::VectorXd r;
  Eigen::MatrixXd j;
  ASSERT_TRUE(model.evaluate(random_log_stiffness(p), r, &j));
  ASSERT_GT(p, r.size());  // the dual (per-spring) regime
  // Some springs frozen (weight 0), as an active bound does.
  Eigen::VectorXd weight = Eigen::VectorXd::Ones(p);
  for (int s = 0; s < p; s += 7) weight[s] = 0.0;
  std::vector<Eigen::Index> rows;
  for (Eigen::Index i = 0; i < r.size(); ++i)
    if (j.row(i).cwiseAbs().maxCoeff() > 0.0) rows.push_back(i);
  Eigen::MatrixXd k, k_squared, g, gram;
  ASSERT_TRUE(model.dual_k_form(weight, rows, k, k_squared, g));
  ASSERT_TRUE(model.gram(weight, gram));
  const Eigen::MatrixXd active = j(rows, Eigen::all) * weight.asDiagonal();
  const Eigen::MatrixXd dense = active * active.transpose();
  const double a = 1e-3 * dense.diagonal().maxCoeff();
  const auto n = static_cast<Eigen::Index>(rows.size());
  const Eigen::MatrixXd k_inverse = k.llt().solve(Eigen::MatrixXd::Identity(n, n));
  const Eigen::MatrixXd from_k_form = k_inverse * (a * k_squared + g) * k_inverse;
  const Eigen::MatrixXd from_gram =
      Eigen::MatrixXd(gram(rows, rows)) + a * Eigen::MatrixXd::Identity(n, n);
  const Eigen::MatrixXd from_dense = dense + a * Eigen::MatrixXd::Identity(n, n);
  EXPECT_LT((from_k_form - from_dense).norm(), 1e-12 * from_dense.norm());
  EXPECT_LT((from_gram - from_dense).norm(), 1e-12 * from_dense.norm());
  EXPECT_LT((k * k - k_squared).norm(), 1e-13 * k_squared.norm());  // K^2 really is K K
}

// One LM step with a shared prior and frozen parameters, with the system from the K form, from
// gram() and from the dense product: the same step.
TEST(DualKForm, LevenbergMarquardtStepIsTheSameWithEveryForm) {
  const DisplacementFitData data = one_case_data();
  const Grouping grouping = one_group_per_spring(data.network);
  const Grouping lengths = group_by_rest_length(data.network, 0.01);
  detail::DisplacementModel model(data, grouping);
  const int p = grouping.num_groups();
  const Eigen::VectorXd start = random_log_stiffness(p);
  Eigen::VectorXd steps[3];
  bool k_form_used = false;
  int frozen = 0;
  for (int form = 0; form < 3; ++form) {
    detail::BoundedLeastSquares problem;
    problem.evaluate = [&model](const Eigen::VectorXd& x, Eigen::VectorXd& r, Eigen::MatrixXd* j) {
      return model.evaluate(x, r, j);
    };
    if (form == 0)
      problem.k_form = [&](const Eigen::VectorXd& w, const std::vector<Eigen::Index>& rows,
                           Eigen::MatrixXd& k, Eigen::MatrixXd& k2, Eigen::MatrixXd& g) {
        const bool used = model.dual_k_form(w, rows, k, k2, g);
        frozen = static_cast<int>((w.array() == 0.0).count());
        k_form_used = k_form_used || used;
        return used;
      };
    if (form <= 1)
      problem.gram = [&model](const Eigen::VectorXd& w, Eigen::MatrixXd& gram) {
        return model.gram(w, gram);
      };
    // Every 5th spring sits on its lower bound; the data gradient pushes about half of them
    // outwards, which freezes them.
    problem.lower = Eigen::VectorXd::Constant(p, -INFINITY);
    for (int s = 0; s < p; s += 5) problem.lower[s] = start[s];
    problem.upper = Eigen::VectorXd::Constant(p, INFINITY);
    problem.prior_groups = lengths.group_of_spring;
    problem.prior_weight = 1e-4;
    detail::DualLmOptions options;
    options.max_iterations = 1;
    Eigen::VectorXd x = start;
    detail::solve_dual_levenberg_marquardt(problem, x, options);
    steps[form] = x - start;
  }
  ASSERT_TRUE(k_form_used);
  ASSERT_GT(frozen, 0);
  ASSERT_GT(steps[2].norm(), 1e-3 * start.norm());  // an accepted, non-trivial step
  EXPECT_LT((steps[0] - steps[2]).norm(), 1e-12 * steps[2].norm());
  EXPECT_LT((steps[1] - steps[2]).norm(), 1e-12 * steps[2].norm());
}

}  // namespace
}  // namespace isospring::fitting
