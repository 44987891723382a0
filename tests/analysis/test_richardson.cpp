// Richardson extrapolation: exact on pure power laws, the leading-order error on mixed ones, and
// clear statuses when there is no monotone convergence to extrapolate.
#include <gtest/gtest.h>

#include <cmath>

#include "isospring/analysis/richardson.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::analysis {
namespace {

TEST(Richardson, RecoversAPurePowerLawExactly) {
  for (double ratio : {2.0, 3.0})
    for (double p : {1.0, 2.5, 4.0}) {
      auto q = [&](double h) { return 7.25 - 0.8 * std::pow(h, p); };
      const Richardson r =
          richardson_extrapolation(q(0.5), q(0.5 / ratio), q(0.5 / ratio / ratio), ratio);
      ASSERT_TRUE(r.extrapolated());
      // Round-off only: the differences lose ~log10(1 / h^p) digits of 7.25.
      EXPECT_NEAR(r.order, p, 1e-9) << "ratio " << ratio;
      EXPECT_NEAR(r.value, 7.25, 1e-12) << "ratio " << ratio;
      EXPECT_NEAR(r.error_estimate, 0.8 * std::pow(0.5 / ratio / ratio, p), 1e-12);
    }
}

TEST(Richardson, HigherOrderTermsLeaveAnErrorOfTheNextOrder) {
  // q = 1 + h^2 + h^3: the extrapolated value's error is O(h^3), far below the finest's h^2.
  auto q = [](double h) { return 1.0 + h * h + h * h * h; };
  const double h = 0.05;
  const Richardson r = richardson_extrapolation(q(h), q(h / 2), q(h / 4));
  ASSERT_TRUE(r.extrapolated());
  EXPECT_NEAR(r.order, 2.0, 0.05);
  // With the order fixed at 2 the remainder would be h_f^3 (1 + (1 - 8) / 3) = -4/3 h_f^3
  // (h_f = h / 4); the estimated order (2.04) adds a little (measured 1.66 h_f^3).
  EXPECT_LT(std::abs(r.value - 1.0), 2.0 * std::pow(h / 4, 3));
  EXPECT_GT(std::abs(q(h / 4) - 1.0), 10 * std::abs(r.value - 1.0));
}

TEST(Richardson, ReportsWhatCannotBeExtrapolated) {
  const Richardson oscillating = richardson_extrapolation(1.0, 1.1, 1.05);
  EXPECT_EQ(oscillating.status, Richardson::Status::kOscillating);
  EXPECT_EQ(oscillating.value, 1.05);
  EXPECT_NEAR(oscillating.error_estimate, 0.05, 1e-15);
  EXPECT_TRUE(std::isnan(oscillating.order));
  EXPECT_EQ(richardson_extrapolation(1.0, 1.1, 1.3).status, Richardson::Status::kDiverging);
  EXPECT_EQ(richardson_extrapolation(1.0, 1.0, 1.3).status, Richardson::Status::kDiverging);
  // A change of 1e-11 relative is round-off: the sequence has converged.
  const Richardson converged = richardson_extrapolation(2.0, 2.0 + 1e-9, 2.0 + 1e-9 + 2e-11);
  EXPECT_EQ(converged.status, Richardson::Status::kConverged);
  EXPECT_EQ(status_name(converged.status), "converged");
  EXPECT_THROW(richardson_extrapolation(1, 2, 3, 1.0), nurbs::InputError);
  EXPECT_THROW(richardson_extrapolation(1, NAN, 3), std::runtime_error);
}

}  // namespace
}  // namespace isospring::analysis
