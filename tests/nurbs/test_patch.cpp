// Patch evaluation: rational basis identities, derivatives against finite differences, exact
// conics.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "isospring/nurbs/error.hpp"
#include "isospring/nurbs/patch.hpp"
#include "random_patch.hpp"

using namespace isospring::nurbs;
using isospring::testing::random_param;
using isospring::testing::random_patch;

namespace {
// Quarter circle of radius r as a rational quadratic curve (weights 1, 1/sqrt2, 1).
Patch quarter_circle(double r) {
  return Patch({KnotVector(2, {0, 0, 0, 1, 1, 1})},
               {Eigen::Vector3d(r, 0, 0), Eigen::Vector3d(r, r, 0), Eigen::Vector3d(0, r, 0)},
               {1.0, std::sqrt(0.5), 1.0});
}
}  // namespace

TEST(Patch, RationalBasisIsAPartitionOfUnityAndReproducesPoints) {
  std::mt19937 rng(3);
  for (int dim = 1; dim <= 3; ++dim)
    for (int trial = 0; trial < 20; ++trial) {
      const Patch patch = random_patch(rng, dim, 4, true);
      for (int q = 0; q < 20; ++q) {
        const Param u = random_param(rng, patch);
        const RationalBasis r = patch.basis(u, 2);
        EXPECT_NEAR(r.values.sum(), 1.0, 1e-13);
        EXPECT_GE(r.values.minCoeff(), 0.0);
        EXPECT_LT(r.first.colwise().sum().cwiseAbs().maxCoeff(), 1e-10);
        EXPECT_LT(r.second.colwise().sum().cwiseAbs().maxCoeff(), 1e-8);
        Eigen::Vector3d x = Eigen::Vector3d::Zero();
        for (size_t i = 0; i < r.indices.size(); ++i)
          x += r.values(static_cast<Eigen::Index>(i)) * patch.control_point(r.indices[i]);
        EXPECT_LT((x - patch.point(u)).norm(), 1e-13);
      }
    }
}

TEST(Patch, DerivativesMatchCentralDifferences) {
  std::mt19937 rng(4);
  for (int dim = 1; dim <= 3; ++dim)
    for (int trial = 0; trial < 10; ++trial) {
      // No interior knots: the patch is smooth everywhere, so differences never cross a kink.
      const Patch patch = random_patch(rng, dim, 4, true, 0);
      const Param u = random_param(rng, patch);
      const PatchDerivatives der = patch.derivatives(u, 2);
      const RationalBasis basis = patch.basis(u, 2);
      const double h = 1e-5;
      for (int a = 0; a < dim; ++a) {
        Param lo = u, hi = u;
        lo[a] -= h;
        hi[a] += h;
        const Eigen::Vector3d fd = (patch.point(hi) - patch.point(lo)) / (2 * h);
        EXPECT_LT((der.first.col(a) - fd).norm(), 1e-7 * (1 + fd.norm()));
        const PatchDerivatives dlo = patch.derivatives(lo, 1), dhi = patch.derivatives(hi, 1);
        for (int b = 0; b < dim; ++b) {
          const Eigen::Vector3d fd2 = (dhi.first.col(b) - dlo.first.col(b)) / (2 * h);
          EXPECT_LT((der.second[a].col(b) - fd2).norm(), 1e-5 * (1 + fd2.norm()));
        }
        // Rational basis derivatives against differences of the basis values.
        const RationalBasis rlo = patch.basis(lo, 0), rhi = patch.basis(hi, 0);
        for (int i = 0; i < basis.values.size(); ++i)
          EXPECT_NEAR(basis.first(i, a), (rhi.values(i) - rlo.values(i)) / (2 * h), 1e-7);
      }
    }
}

TEST(Patch, QuarterCircleIsExact) {
  const Patch arc = quarter_circle(2.5);
  for (int q = 0; q <= 1000; ++q) {
    const Eigen::Vector3d x = arc.point({q / 1000.0, 0, 0});
    EXPECT_NEAR(x.norm(), 2.5, 2.5e-15);
  }
}

TEST(Patch, NetIndexingAndDimensions) {
  std::mt19937 rng(5);
  const Patch patch = random_patch(rng, 3, 3, false);
  for (int i = 0; i < patch.num_points(); ++i) {
    const auto ijk = patch.net_position(i);
    EXPECT_EQ(patch.index(ijk[0], ijk[1], ijk[2]), i);
  }
  EXPECT_EQ(patch.physical_dim(), 3);
  EXPECT_FALSE(patch.is_rational());
  const Patch flat({KnotVector(1, {0, 0, 1, 1}), KnotVector(1, {0, 0, 1, 1})},
                   {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}});
  EXPECT_EQ(flat.physical_dim(), 2);
  EXPECT_EQ(flat.num_elements(), 1);
}

TEST(Patch, RejectsInconsistentInput) {
  const KnotVector kv(1, {0, 0, 1, 1});
  EXPECT_THROW(Patch({kv}, {{0, 0, 0}}), InputError);                          // too few
  EXPECT_THROW(Patch({kv}, {{0, 0, 0}, {1, 0, 0}}, {1.0, 0.0}), InputError);   // w = 0
  EXPECT_THROW(Patch({kv}, {{0, 0, 0}, {1, 0, 0}}, {1.0, -2.0}), InputError);  // w < 0
  EXPECT_THROW(Patch({kv}, {{0, 0, 0}, {NAN, 0, 0}}), InputError);             // NaN
  EXPECT_THROW(Patch({kv}, {{0, 0, 0}, {1, 0, 0}}, {1.0}), InputError);        // count
  try {
    Patch({kv}, {{0, 0, 0}, {1, 0, 0}}, {1.0, -2.0});
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("weights[1]"), std::string::npos);
  }
}

#include "isospring/nurbs/batch_evaluation.hpp"

TEST(Patch, BatchEvaluationAgreesWithSinglePointEvaluation) {
  std::mt19937 rng(15);
  for (int dim = 1; dim <= 3; ++dim)
    for (int trial = 0; trial < 6; ++trial) {
      const Patch patch = random_patch(rng, dim, 4, trial % 2 == 1);
      std::vector<Param> params;
      for (int q = 0; q < 100; ++q) params.push_back(random_param(rng, patch));
      Eigen::Matrix3Xd points, first;
      BatchEvaluator(patch).evaluate(params, points, &first);
      for (size_t q = 0; q < params.size(); ++q) {
        const PatchDerivatives der = patch.derivatives(params[q], 1);
        EXPECT_LT((points.col(static_cast<Eigen::Index>(q)) - der.point).norm(), 1e-13);
        for (int a = 0; a < dim; ++a)
          EXPECT_LT((first.col(dim * static_cast<Eigen::Index>(q) + a) - der.first.col(a)).norm(),
                    1e-12 * (1 + der.first.col(a).norm()));
      }
    }
}
