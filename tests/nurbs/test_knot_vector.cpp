#include <gtest/gtest.h>

#include <cmath>

#include "isospring/nurbs/error.hpp"
#include "isospring/nurbs/knot_vector.hpp"

using namespace isospring::nurbs;

TEST(KnotVector, SpansUniqueAndMultiplicities) {
  const KnotVector kv(2, {0, 0, 0, 0.25, 0.5, 0.5, 1, 1, 1});
  EXPECT_EQ(kv.num_basis(), 6);
  EXPECT_EQ(kv.find_span(0.0), 2);
  EXPECT_EQ(kv.find_span(0.1), 2);
  EXPECT_EQ(kv.find_span(0.25), 3);
  EXPECT_EQ(kv.find_span(0.49), 3);
  EXPECT_EQ(kv.find_span(0.5), 5);
  EXPECT_EQ(kv.find_span(1.0), 5);  // the end belongs to the last non-empty span
  EXPECT_EQ(kv.unique(), (std::vector<double>{0, 0.25, 0.5, 1}));
  EXPECT_EQ(kv.multiplicities(), (std::vector<int>{3, 1, 2, 3}));
  EXPECT_EQ(kv.multiplicity(0.5), 2);
  EXPECT_EQ(kv.multiplicity(0.3), 0);
  EXPECT_EQ(kv.num_elements(), 3);
  EXPECT_EQ(kv.element_spans(), (std::vector<int>{2, 3, 5}));
}

TEST(KnotVector, Uniform) {
  const KnotVector kv = KnotVector::uniform(3, 4, -1.0, 1.0);
  EXPECT_EQ(kv.values(), (std::vector<double>{-1, -1, -1, -1, -0.5, 0, 0.5, 1, 1, 1, 1}));
}

TEST(KnotVector, RejectsBadInputWithAReason) {
  auto problem = [](int p, std::vector<double> k, int n = -1) {
    return check_knot_vector(p, k, n);
  };
  EXPECT_EQ(problem(2, {0, 0, 0, 1, 1, 1}), "");
  EXPECT_NE(problem(2, {0, 0, 0, 0.6, 0.4, 1, 1, 1}).find("must not decrease"), std::string::npos);
  EXPECT_NE(problem(2, {0, 0, 0.5, 1, 1, 1}).find("not clamped"), std::string::npos);
  EXPECT_NE(problem(2, {0, 0, 0, 0.5, 0.5, 0.5, 1, 1, 1}).find("multiplicity above the degree"),
            std::string::npos);
  EXPECT_NE(problem(2, {0, 0, 0, NAN, 1, 1, 1}).find("not a finite number"), std::string::npos);
  EXPECT_NE(problem(2, {0, 0, 0, 1, 1, 1}, 4).find("control points"), std::string::npos);
  EXPECT_NE(problem(0, {0, 1}).find("degree 0"), std::string::npos);
  EXPECT_NE(problem(2, {1, 1, 1, 1, 1, 1}).find("all knots are equal"), std::string::npos);
  EXPECT_THROW(KnotVector(1, {0, 0.5, 1, 1}, "patch 0 knots[0]"), InputError);
  try {
    KnotVector(1, {0, 0.5, 1, 1}, "patch 0 knots[0]");
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("patch 0 knots[0]"), std::string::npos);
  }
}
