// Refinement never changes geometry: random patches of degree 1..4 in parametric dimension 1..3,
// rational and not, refined by every operation, agree at 1000+ random parameters to 1e-12
// (relative to the patch size). Exact conics keep their radius to 1e-14.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "isospring/nurbs/basis.hpp"
#include "isospring/nurbs/bezier_extraction.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/nurbs/refine.hpp"
#include "random_patch.hpp"

using namespace isospring::nurbs;
using isospring::testing::random_param;
using isospring::testing::random_patch;

namespace {

double max_deviation(const Patch& a, const Patch& b, std::mt19937& rng, int samples) {
  double worst = 0.0;
  for (int q = 0; q < samples; ++q) {
    const Param u = random_param(rng, a);
    worst = std::max(worst, (a.point(u) - b.point(u)).norm());
  }
  return worst;
}

double size_of(const Patch& patch) {
  const auto [lo, hi] = patch.control_bounds();
  return (hi - lo).norm();
}

Patch quarter_annulus(double r0, double r1) {
  const double w = std::sqrt(0.5);
  return Patch({KnotVector(2, {0, 0, 0, 1, 1, 1}), KnotVector(1, {0, 0, 1, 1})},
               {{r0, 0, 0}, {r0, r0, 0}, {0, r0, 0}, {r1, 0, 0}, {r1, r1, 0}, {0, r1, 0}},
               {1, w, 1, 1, w, 1});
}

Patch full_circle() {
  // Nine-point rational quadratic circle of radius 1 (knots with double interior knots).
  const double w = std::sqrt(0.5);
  return Patch({KnotVector(2, {0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1})},
               {{1, 0, 0},
                {1, 1, 0},
                {0, 1, 0},
                {-1, 1, 0},
                {-1, 0, 0},
                {-1, -1, 0},
                {0, -1, 0},
                {1, -1, 0},
                {1, 0, 0}},
               {1, w, 1, w, 1, w, 1, w, 1});
}

}  // namespace

class RefinementPreservesGeometry : public ::testing::TestWithParam<int> {};

TEST_P(RefinementPreservesGeometry, EveryOperation) {
  const int dim = GetParam();
  std::mt19937 rng(100 + dim);
  int checked = 0;
  for (int trial = 0; trial < 8; ++trial) {
    const bool rational = trial % 2 == 1;
    const Patch patch = random_patch(rng, dim, 4, rational);
    const double tolerance = 1e-12 * size_of(patch);
    std::uniform_real_distribution<double> unit(0.01, 0.99);
    for (int dir = 0; dir < dim; ++dir) {
      const double u = unit(rng);
      const Patch once = insert_knot(patch, dir, u);
      const Patch twice = insert_knot(patch, dir, u, std::min(2, patch.degree(dir)));
      const Patch many = refine_knots(patch, dir, {unit(rng), unit(rng), unit(rng)});
      const Patch split = refine_uniform(patch, dir, 3);
      const Patch elevated = elevate_degree(patch, dir, 1 + trial % 3);
      EXPECT_EQ(once.num_points(dir), patch.num_points(dir) + 1);
      EXPECT_EQ(elevated.degree(dir), patch.degree(dir) + 1 + trial % 3);
      for (const Patch* refined : {&once, &twice, &many, &split, &elevated}) {
        EXPECT_LT(max_deviation(patch, *refined, rng, 250), tolerance);
        checked += 250;
      }
    }
    const Patch k = k_refine(patch, {5, 5, 5}, {2, 2, 2});
    EXPECT_LT(max_deviation(patch, k, rng, 250), tolerance);
    for (int dir = 0; dir < dim; ++dir) EXPECT_EQ(k.degree(dir), 5);
    checked += 250;
  }
  EXPECT_GE(checked, 1000);
}

INSTANTIATE_TEST_SUITE_P(ParametricDimension, RefinementPreservesGeometry,
                         ::testing::Values(1, 2, 3));

TEST(Refinement, DegreeElevationKeepsInteriorContinuity) {
  // Elevating p -> p+t keeps each interior knot's continuity p - m, so multiplicities rise by t.
  const Patch curve({KnotVector(2, {0, 0, 0, 0.3, 0.6, 0.6, 1, 1, 1})},
                    {{0, 0, 0}, {1, 2, 0}, {2, -1, 0}, {3, 1, 0}, {4, 0, 0}, {5, 3, 0}});
  const Patch elevated = elevate_degree(curve, 0, 2);
  EXPECT_EQ(elevated.knots(0).values(),
            (std::vector<double>{0, 0, 0, 0, 0, 0.3, 0.3, 0.3, 0.6, 0.6, 0.6, 0.6, 1, 1, 1, 1, 1}));
}

TEST(Refinement, ExactConicsKeepTheirRadius) {
  std::mt19937 rng(7);
  const Patch circle = full_circle();
  const Patch annulus = quarter_annulus(1.0, 2.0);
  const std::vector<Patch> circles = {
      circle, refine_uniform(circle, 0, 7), elevate_degree(circle, 0, 3),
      k_refine(circle, {4, 0, 0}, {5, 1, 1}), refine_knots(circle, 0, {0.1, 0.13, 0.6, 0.99})};
  for (const Patch& c : circles)
    for (int q = 0; q < 500; ++q) EXPECT_NEAR(c.point(random_param(rng, c)).norm(), 1.0, 1e-14);
  const std::vector<Patch> annuli = {refine_uniform(annulus, 6), elevate_degree(annulus, 2),
                                     k_refine(annulus, {3, 3, 0}, {4, 4, 1})};
  for (const Patch& a : annuli)
    for (int q = 0; q < 500; ++q) {
      // On the inner and outer arcs (v = 0, 1) the radius is exact.
      Param u = random_param(rng, a);
      u[1] = 0.0;
      EXPECT_NEAR(a.point(u).norm(), 1.0, 1e-14);
      u[1] = 1.0;
      EXPECT_NEAR(a.point(u).norm(), 2.0, 2e-14);
    }
}

TEST(Refinement, RejectsImpossibleRequests) {
  const Patch arc = quarter_annulus(1.0, 2.0);
  EXPECT_THROW(insert_knot(arc, 0, 1.5), InputError);     // outside the range
  EXPECT_THROW(insert_knot(arc, 0, 0.5, 3), InputError);  // multiplicity above degree 2
  EXPECT_THROW(insert_knot(arc, 2, 0.5), InputError);     // no third direction
  EXPECT_THROW(elevate_degree(arc, 0, -1), InputError);
  EXPECT_THROW(refine_uniform(arc, 0, 0), InputError);
  EXPECT_THROW(k_refine(arc, {1, 1, 0}, {1, 1, 1}), InputError);  // lowering the degree
}

TEST(BezierExtraction, ReproducesTheBasisOnEveryElement) {
  std::mt19937 rng(8);
  for (int p = 1; p <= 5; ++p) {
    const KnotVector kv = isospring::testing::random_knots(rng, p, 6);
    const auto operators = bezier_extraction(kv);
    const std::vector<double> breaks = kv.unique();
    const std::vector<int> spans = kv.element_spans();
    ASSERT_EQ(operators.size(), spans.size());
    for (size_t e = 0; e < spans.size(); ++e)
      for (double t : {0.0, 0.13, 0.5, 0.91, 1.0}) {
        const double u = breaks[e] + t * (breaks[e + 1] - breaks[e]);
        Eigen::VectorXd n(p + 1);
        basis_derivatives(kv, spans[e], u, 0, n.data());
        const Eigen::VectorXd via_bezier = operators[e] * bernstein(p, t).row(0).transpose();
        EXPECT_LT((n - via_bezier).cwiseAbs().maxCoeff(), 1e-13);
      }
  }
}
