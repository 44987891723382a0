// The Lame split of the B-bar stiffness (identify's stiffness parameters on a B-bar reference):
// its sum against the B-bar stiffness assembled directly, and each weighted part against the
// B-bar energy integrated through the post-processing path (FieldEvaluator's projected
// dilatation and B-bar strain), which shares neither the split's algebra nor its assembly.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/elasticity.hpp"
#include "isospring/analysis/lame_stiffness.hpp"
#include "isospring/analysis/post_processing.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/nurbs/quadrature.hpp"
#include "isospring/nurbs/refine.hpp"
#include "lame_cylinder.hpp"

namespace isospring::analysis {
namespace {

// A distorted box 2 x 1 x 0.5 (curved faces, non-affine map), degree p, n x 2 x 2 elements,
// nearly incompressible.
Problem distorted_box(int p, int n) {
  const nurbs::KnotVector linear(1, {0, 0, 1, 1});
  std::vector<Eigen::Vector3d> corners;
  for (int z = 0; z < 2; ++z)
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 2; ++x) corners.emplace_back(2.0 * x, 1.0 * y, 0.5 * z);
  nurbs::Patch patch =
      nurbs::k_refine(nurbs::Patch({linear, linear, linear}, corners), {p, p, p}, {n, 2, 2});
  std::vector<Eigen::Vector3d> points = patch.control_points();
  for (Eigen::Vector3d& x : points)
    x += Eigen::Vector3d(0.05 * std::sin(3.0 * x.y() + x.z()), 0.04 * std::sin(2.0 * x.x()),
                         0.03 * std::cos(x.x() + 2.0 * x.y()));
  Problem problem;
  problem.formulation = Formulation::kSolid;
  problem.volumetric = Volumetric::kBbar;
  problem.material = {1e6, 0.49, 1000.0, 1.0};
  std::vector<nurbs::KnotVector> knots;
  for (int d = 0; d < 3; ++d) knots.push_back(patch.knots(d));
  problem.patches.emplace_back(knots, points, patch.weights());
  return problem;
}

double relative_difference(const Eigen::SparseMatrix<double>& a,
                           const Eigen::SparseMatrix<double>& b) {
  return Eigen::SparseMatrix<double>(a - b).norm() / b.norm();
}

// lambda K_lambda + mu K_mu is the B-bar stiffness of assemble_stiffness (full, both triangles),
// in 3D (distorted box, p = 2 and 3) and plane strain (the Lame ring, rational, p = 2 and 3).
TEST(BbarLameParts, SumIsTheAssembledBbarStiffness) {
  std::vector<Problem> problems{distorted_box(2, 3), distorted_box(3, 2)};
  for (int p : {2, 3}) {
    Problem ring = testing::lame_cylinder({1e5, 0.4999, 100.0}, testing::lame_ring(p, 4));
    ring.volumetric = Volumetric::kBbar;
    problems.push_back(ring);
  }
  for (const Problem& problem : problems) {
    const DofMap dofs(problem);
    const LameParameters lame = lame_parameters(problem.material, problem.formulation);
    const LameStiffness parts = assemble_lame_stiffness(problem, dofs, {SpatialWeight()}).front();
    const Eigen::SparseMatrix<double> direct =
        assemble_stiffness(problem, dofs).selfadjointView<Eigen::Upper>();
    const Eigen::SparseMatrix<double> sum =
        lame.lambda * parts.lambda_part + lame.mu * parts.mu_part;
    const double difference = relative_difference(sum, direct);
    std::printf("B-bar Lame split, %d DOFs: |sum - direct| / |direct| = %.2e\n", dofs.num_dofs(),
                difference);
    // Sums of the same products in another order (and lambda ~ 50 mu at 0.49, 5000 mu at
    // 0.4999, so the parts cancel in K's deviatoric entries): rounding only.
    EXPECT_LT(difference, 1e-12);
    // Symmetric (full matrices), as the displacement formulation's parts.
    EXPECT_LT(relative_difference(Eigen::SparseMatrix<double>(parts.lambda_part.transpose()),
                                  parts.lambda_part),
              1e-14);
    EXPECT_LT(
        relative_difference(Eigen::SparseMatrix<double>(parts.mu_part.transpose()), parts.mu_part),
        1e-14);
  }
}

// With a weight w(x), u^T K_lambda u = int w theta_bar^2 and
// u^T K_mu u = int w (2 |dev eps|^2 + 2/3 theta_bar^2) for any u, theta_bar = Pi div u: both
// integrated here point by point from FieldEvaluator's B-bar strain (trace theta_bar, deviator
// that of eps) with the solve's Gauss rule (p + 1 points, the rule the projection is defined by).
TEST(BbarLameParts, WeightedPartsIntegrateTheBbarEnergy) {
  const Problem problem = distorted_box(2, 3);
  const DofMap dofs(problem);
  const SpatialWeight weight = [](const Eigen::Vector3d& x) {
    return 1.0 + 0.4 * x.x() + 0.3 * std::sin(4.0 * x.y());
  };
  const std::vector<LameStiffness> parts =
      assemble_lame_stiffness(problem, dofs, {weight, SpatialWeight()});
  ASSERT_EQ(parts.size(), 2u);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const nurbs::Patch& patch = problem.patches[0];
  ControlDisplacements u(1, std::vector<Eigen::Vector3d>(static_cast<size_t>(patch.num_points())));
  Eigen::VectorXd vector = Eigen::VectorXd::Zero(dofs.num_dofs());
  for (int a = 0; a < patch.num_points(); ++a) {
    u[0][static_cast<size_t>(a)] = Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
    for (int i = 0; i < 3; ++i) vector[dofs.dof(0, a, i)] = u[0][static_cast<size_t>(a)][i];
  }
  const FieldEvaluator field(problem, u);
  const nurbs::GaussRule gauss = nurbs::gauss_legendre(3);
  std::array<std::vector<double>, 3> breaks;
  for (int d = 0; d < 3; ++d) breaks[static_cast<size_t>(d)] = patch.knots(d).unique();
  double volumetric[2] = {0.0, 0.0}, shear[2] = {0.0, 0.0};
  for (size_t i = 0; i + 1 < breaks[0].size(); ++i)
    for (size_t j = 0; j + 1 < breaks[1].size(); ++j)
      for (size_t k = 0; k + 1 < breaks[2].size(); ++k)
        for (size_t a = 0; a < 3; ++a)
          for (size_t b = 0; b < 3; ++b)
            for (size_t c = 0; c < 3; ++c) {
              const size_t span[3] = {i, j, k}, q[3] = {a, b, c};
              nurbs::Param x{};
              double dv = 1.0;
              for (size_t d = 0; d < 3; ++d) {
                const double lo = breaks[d][span[d]], h = breaks[d][span[d] + 1] - lo;
                x[d] = lo + 0.5 * h * (1.0 + gauss.points[q[d]]);
                dv *= 0.5 * h * gauss.weights[q[d]];
              }
              dv *= patch.derivatives(x, 1).first.determinant();
              const FieldPoint f = field(0, x);
              const double theta = f.strain.trace();
              const Eigen::Matrix3d deviator = f.strain - theta / 3.0 * Eigen::Matrix3d::Identity();
              const double w[2] = {weight(f.point), 1.0};
              for (int m = 0; m < 2; ++m) {
                volumetric[m] += w[m] * theta * theta * dv;
                shear[m] += w[m] * (2.0 * deviator.squaredNorm() + 2.0 / 3.0 * theta * theta) * dv;
              }
            }
  for (int m = 0; m < 2; ++m) {
    const double kl = vector.dot(parts[static_cast<size_t>(m)].lambda_part * vector);
    const double km = vector.dot(parts[static_cast<size_t>(m)].mu_part * vector);
    std::printf("weight %d: u^T K_lambda u %.12e vs %.12e, u^T K_mu u %.12e vs %.12e\n", m, kl,
                volumetric[m], km, shear[m]);
    EXPECT_NEAR(kl, volumetric[m], 1e-11 * volumetric[m]);
    EXPECT_NEAR(km, shear[m], 1e-11 * shear[m]);
  }
  // The weight matters: the weighted and unweighted volumetric energies differ by far more.
  EXPECT_GT(std::abs(volumetric[0] - volumetric[1]), 1e-3 * volumetric[1]);
}

// Plane stress does not lock: a B-bar plane-stress problem is refused with the reason.
TEST(BbarLameParts, PlaneStressIsRefused) {
  Problem problem = testing::lame_cylinder({1e5, 0.3, 100.0}, testing::lame_ring(2, 2));
  problem.formulation = Formulation::kPlaneStress;
  problem.volumetric = Volumetric::kBbar;
  const DofMap dofs(problem);
  try {
    assemble_lame_stiffness(problem, dofs, {SpatialWeight()});
    FAIL() << "B-bar in plane stress was accepted";
  } catch (const nurbs::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("plane stress"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace isospring::analysis
