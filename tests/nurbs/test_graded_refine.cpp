// Graded knot insertion (graded_refine.hpp): the breakpoints against their closed form, the
// geometry unchanged to round-off, and the reason for grading measured as a rate: the L2
// projection of t^a onto splines converges at h^(a + 1/2) on uniform knots and at
// h^min(p + 1, exponent (a + 1/2)) on knots graded towards t = 0 (the classical result for
// radical meshes, e.g. de Boor, A Practical Guide to Splines, XII; Rice 1969).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <random>

#include "isospring/nurbs/basis.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/nurbs/graded_refine.hpp"
#include "isospring/nurbs/quadrature.hpp"
#include "isospring/nurbs/refine.hpp"
#include "random_patch.hpp"

using namespace isospring::nurbs;

namespace {

TEST(GradedRefine, BreakpointsMatchTheirClosedForm) {
  // Towards the start: a + (b - a) (i / n)^e.
  const std::vector<double> start = graded_breakpoints(1.0, 3.0, 4, {2.0, true, false});
  const std::vector<double> expected_start{1.0, 1.0 + 2.0 / 16, 1.0 + 2.0 / 4, 1.0 + 18.0 / 16,
                                           3.0};
  ASSERT_EQ(start.size(), expected_start.size());
  for (size_t i = 0; i < start.size(); ++i) EXPECT_NEAR(start[i], expected_start[i], 1e-15);
  // Towards the end: the mirror image.
  const std::vector<double> end = graded_breakpoints(0.0, 1.0, 3, {3.0, false, true});
  EXPECT_NEAR(end[1], 1.0 - std::pow(2.0 / 3.0, 3), 1e-15);
  EXPECT_NEAR(end[2], 1.0 - std::pow(1.0 / 3.0, 3), 1e-15);
  // Both ends: each half graded, symmetric about the middle.
  const std::vector<double> both = graded_breakpoints(0.0, 1.0, 6, {2.0, true, true});
  EXPECT_NEAR(both[1], 0.5 * std::pow(1.0 / 3.0, 2), 1e-15);
  EXPECT_NEAR(both[3], 0.5, 1e-15);
  for (size_t i = 0; i < both.size(); ++i) EXPECT_NEAR(both[i] + both[6 - i], 1.0, 1e-15);
  // Exponent 1 is uniform.
  const std::vector<double> uniform = graded_breakpoints(0.0, 1.0, 5, {1.0, true, true});
  for (int i = 0; i <= 5; ++i) EXPECT_NEAR(uniform[static_cast<size_t>(i)], i / 5.0, 1e-15);
}

TEST(GradedRefine, RefusesBadInput) {
  EXPECT_THROW(graded_breakpoints(0, 1, 0, {2.0, true, false}), InputError);
  EXPECT_THROW(graded_breakpoints(0, 1, 4, {0.5, true, false}), InputError);
  EXPECT_THROW(graded_breakpoints(1, 1, 4, {2.0, true, false}), InputError);
  const Patch line({KnotVector(1, {0, 0, 1, 1})}, {{0, 0, 0}, {1, 0, 0}});
  EXPECT_THROW(refine_graded(line, 1, 4, {2.0, true, false}), InputError);
}

// Random patches (rational and not, degree 1..4, 1..3 parametric directions) graded in every
// direction agree with the original at random parameters to 1e-13 of their size, and the knots
// inserted are the breakpoints (existing knots kept once).
TEST(GradedRefine, GeometryAndParametrisationUnchanged) {
  std::mt19937 rng(31);
  for (int trial = 0; trial < 30; ++trial) {
    const int dim = 1 + trial % 3;
    const Patch patch = isospring::testing::random_patch(rng, dim, 1 + trial % 4, trial % 2 == 0);
    Patch graded = patch;
    for (int d = 0; d < dim; ++d)
      graded = refine_graded(graded, d, 3 + trial % 5, {1.0 + 0.5 * (trial % 4), d != 1, d != 0});
    const auto [lo, hi] = patch.control_bounds();
    const double size = (hi - lo).norm();
    for (int q = 0; q < 200; ++q) {
      const Param u = isospring::testing::random_param(rng, patch);
      EXPECT_LE((graded.point(u) - patch.point(u)).norm(), 1e-13 * size) << "trial " << trial;
    }
    for (int d = 0; d < dim; ++d) {
      const std::vector<double> knots = graded.knots(d).unique();
      const Grading g{1.0 + 0.5 * (trial % 4), d != 1, d != 0};
      for (double b :
           graded_breakpoints(patch.knots(d).first(), patch.knots(d).last(), 3 + trial % 5, g)) {
        bool found = false;
        for (double k : knots) found = found || std::abs(k - b) < 1e-12;
        EXPECT_TRUE(found) << "breakpoint " << b << " of direction " << d;
      }
      EXPECT_GE(static_cast<int>(knots.size()) - 1, 3 + trial % 5);
    }
  }
}

// Relative L2 error of the L2 projection of t^a onto the degree-p splines of `knots` on [0, 1].
// Every span is integrated after the substitution t = t0 + (t1 - t0) s^2, which makes the
// integrands polynomial on the first span (t^a with a = 1/2) and smooth on the others, so a
// 2p + 4 point Gauss rule is exact or near it.
double projection_error(const KnotVector& knots, double a) {
  const int p = knots.degree(), n = knots.num_basis();
  const GaussRule rule = gauss_legendre(2 * p + 4);
  Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n);
  std::vector<double> values(static_cast<size_t>(p) + 1);
  const std::vector<double> breaks = knots.unique();
  auto each_point = [&](auto&& visit) {
    for (size_t e = 0; e + 1 < breaks.size(); ++e)
      for (size_t q = 0; q < rule.points.size(); ++q) {
        const double s = 0.5 * (rule.points[q] + 1.0), h = breaks[e + 1] - breaks[e];
        const double t = breaks[e] + h * s * s, weight = 0.5 * rule.weights[q] * 2.0 * h * s;
        const int span = knots.find_span(t);
        basis_functions(knots, span, t, values.data());
        visit(t, weight, span);
      }
  };
  each_point([&](double t, double w, int span) {
    for (int i = 0; i <= p; ++i) {
      rhs[span - p + i] += w * values[static_cast<size_t>(i)] * std::pow(t, a);
      for (int j = 0; j <= p; ++j)
        gram(span - p + i, span - p + j) +=
            w * values[static_cast<size_t>(i)] * values[static_cast<size_t>(j)];
    }
  });
  const Eigen::VectorXd c = gram.ldlt().solve(rhs);
  double error = 0.0;
  each_point([&](double t, double w, int span) {
    double approx = 0.0;
    for (int i = 0; i <= p; ++i) approx += values[static_cast<size_t>(i)] * c[span - p + i];
    error += w * std::pow(approx - std::pow(t, a), 2);
  });
  return std::sqrt(error * (2.0 * a + 1.0));  // ||t^a||^2 = 1 / (2a + 1)
}

double observed_rate(int p, double exponent, double a) {
  const Patch line({KnotVector(1, {0, 0, 1, 1})}, {{0, 0, 0}, {1, 0, 0}});
  const Patch elevated = elevate_degree(line, 0, p - 1);
  const double coarse =
      projection_error(refine_graded(elevated, 0, 32, {exponent, true, false}).knots(0), a);
  const double fine =
      projection_error(refine_graded(elevated, 0, 64, {exponent, true, false}).knots(0), a);
  const double rate = std::log2(coarse / fine);
  std::printf("degree %d, exponent %.1f: L2 error %.3e (32 spans), %.3e (64), rate %.3f\n", p,
              exponent, coarse, fine, rate);
  return rate;
}

TEST(GradedRefine, GradingRestoresTheRateOfASingularFunction) {
  const double a = 0.5;  // t^(1/2): uniform knots converge at h^1 in L2 whatever the degree
  for (int p : {2, 3}) {
    EXPECT_NEAR(observed_rate(p, 1.0, a), 1.0, 0.02) << "uniform, degree " << p;
    EXPECT_NEAR(observed_rate(p, 2.0, a), 2.0, 0.05) << "exponent 2, degree " << p;
    // Graded beyond exponent (p + 1) / (a + 1/2), the optimal rate p + 1 of smooth functions.
    EXPECT_NEAR(observed_rate(p, p + 2.0, a), p + 1.0, 0.1) << "exponent p + 2, degree " << p;
  }
}

}  // namespace
