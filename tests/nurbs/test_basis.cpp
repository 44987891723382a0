// Basis identities: partition of unity, non-negativity, derivatives against finite differences
// and against the sum rule (derivatives of a partition of unity sum to zero).
#include <gtest/gtest.h>

#include <random>

#include "isospring/nurbs/basis.hpp"
#include "isospring/nurbs/quadrature.hpp"
#include "random_patch.hpp"

using namespace isospring::nurbs;

TEST(Basis, PartitionOfUnityAndNonNegativity) {
  std::mt19937 rng(1);
  for (int p = 1; p <= 6; ++p) {
    const KnotVector kv = isospring::testing::random_knots(rng, p, 5);
    std::uniform_real_distribution<double> dist(0.0, 1.0);
    for (int q = 0; q < 200; ++q) {
      const double u = q == 0 ? 0.0 : q == 1 ? 1.0 : dist(rng);
      const Eigen::MatrixXd ders = basis_derivatives(kv, u, std::min(p, 3));
      EXPECT_NEAR(ders.row(0).sum(), 1.0, 1e-14);
      EXPECT_GE(ders.row(0).minCoeff(), 0.0);
      for (int k = 1; k < ders.rows(); ++k) EXPECT_NEAR(ders.row(k).sum(), 0.0, 1e-9);
    }
  }
}

TEST(Basis, DerivativesMatchCentralDifferences) {
  std::mt19937 rng(2);
  for (int p = 1; p <= 5; ++p) {
    const KnotVector kv = isospring::testing::random_knots(rng, p, 4);
    const std::vector<double> breaks = kv.unique();
    for (size_t e = 0; e + 1 < breaks.size(); ++e) {
      // Stay inside the element: derivatives jump across reduced-continuity knots.
      const double u = 0.5 * (breaks[e] + breaks[e + 1]);
      const double h = 1e-5 * (breaks[e + 1] - breaks[e]);
      const int span = kv.find_span(u);
      std::vector<double> lo(static_cast<size_t>(3 * (p + 1))), hi(lo.size()), mid(lo.size());
      basis_derivatives(kv, span, u - h, 2, lo.data());
      basis_derivatives(kv, span, u + h, 2, hi.data());
      basis_derivatives(kv, span, u, 2, mid.data());
      for (int j = 0; j <= p; ++j) {
        const size_t v = static_cast<size_t>(j), d1 = static_cast<size_t>(p + 1 + j);
        // Central differences are O(h^2) accurate: 1e-6 relative to the derivative scale.
        const double scale1 = 1.0 / (breaks[e + 1] - breaks[e]);
        EXPECT_NEAR(mid[d1], (hi[v] - lo[v]) / (2 * h), 1e-6 * scale1);
        if (p >= 2) {
          EXPECT_NEAR(mid[static_cast<size_t>(2 * (p + 1) + j)], (hi[d1] - lo[d1]) / (2 * h),
                      1e-5 * scale1 * scale1);
        }
      }
    }
  }
}

TEST(Basis, BasisFunctionsAgreeWithDerivativeRoutine) {
  const KnotVector kv(3, {0, 0, 0, 0, 0.2, 0.5, 0.5, 0.9, 1, 1, 1, 1});
  for (double u : {0.0, 0.1, 0.2, 0.45, 0.5, 0.77, 1.0}) {
    const int span = kv.find_span(u);
    double values[4];
    basis_functions(kv, span, u, values);
    const Eigen::MatrixXd ders = basis_derivatives(kv, u, 1);
    for (int j = 0; j < 4; ++j) EXPECT_NEAR(values[j], ders(0, j), 1e-15);
  }
}

TEST(Quadrature, GaussLegendreIsExactToDegree2nMinus1) {
  for (int n = 1; n <= 20; ++n) {
    const GaussRule rule = gauss_legendre(n);
    for (int k = 0; k <= 2 * n - 1; ++k) {
      double sum = 0.0;
      for (int q = 0; q < n; ++q)
        sum +=
            rule.weights[static_cast<size_t>(q)] * std::pow(rule.points[static_cast<size_t>(q)], k);
      const double exact = k % 2 ? 0.0 : 2.0 / (k + 1);
      EXPECT_NEAR(sum, exact, 1e-14) << "n=" << n << " k=" << k;
    }
  }
}

TEST(Basis, FirstDerivativeShortcutMatchesGeneralAlgorithm) {
  std::mt19937 rng(16);
  for (int p = 1; p <= 8; ++p) {
    const KnotVector kv = isospring::testing::random_knots(rng, p, 6);
    std::uniform_real_distribution<double> dist(0.0, 1.0);
    for (int q = 0; q < 100; ++q) {
      const double u = q == 0 ? 0.0 : q == 1 ? 1.0 : dist(rng);
      const int span = kv.find_span(u);
      std::vector<double> fast(static_cast<size_t>(2 * (p + 1))), general(fast.size());
      basis_first_derivatives(kv, span, u, fast.data());
      basis_derivatives(kv, span, u, 1, general.data());
      for (size_t k = 0; k < fast.size(); ++k)
        EXPECT_NEAR(fast[k], general[k], 1e-12 * (1 + std::abs(general[k])));
    }
  }
}
