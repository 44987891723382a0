// Cross-check of the kernel against OpenCascade's own B-spline algorithms (an independent
// implementation): evaluation with first derivatives, knot insertion and degree elevation of
// random B-spline and NURBS curves and surfaces, compared to 1e-12.
#include <gtest/gtest.h>

#include <Geom_BSplineCurve.hxx>
#include <Geom_BSplineSurface.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColStd_Array2OfReal.hxx>
#include <TColgp_Array1OfPnt.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <random>

#include "isospring/nurbs/refine.hpp"
#include "random_patch.hpp"

using namespace isospring::nurbs;
using isospring::testing::random_param;
using isospring::testing::random_patch;

namespace {

constexpr double kTolerance = 1e-12;

void to_occt_knots(const KnotVector& kv, TColStd_Array1OfReal& knots,
                   TColStd_Array1OfInteger& mults) {
  const auto unique = kv.unique();
  const auto counts = kv.multiplicities();
  knots.Resize(1, static_cast<int>(unique.size()), false);
  mults.Resize(1, static_cast<int>(unique.size()), false);
  for (size_t i = 0; i < unique.size(); ++i) {
    knots.SetValue(static_cast<int>(i) + 1, unique[i]);
    mults.SetValue(static_cast<int>(i) + 1, counts[i]);
  }
}

Handle(Geom_BSplineCurve) to_occt_curve(const Patch& patch) {
  const int n = patch.num_points();
  TColgp_Array1OfPnt poles(1, n);
  TColStd_Array1OfReal weights(1, n);
  for (int i = 0; i < n; ++i) {
    const auto& x = patch.control_point(i);
    poles.SetValue(i + 1, gp_Pnt(x.x(), x.y(), x.z()));
    weights.SetValue(i + 1, patch.weight(i));
  }
  TColStd_Array1OfReal knots(1, 1);
  TColStd_Array1OfInteger mults(1, 1);
  to_occt_knots(patch.knots(0), knots, mults);
  return new Geom_BSplineCurve(poles, weights, knots, mults, patch.degree(0));
}

Handle(Geom_BSplineSurface) to_occt_surface(const Patch& patch) {
  const int nu = patch.num_points(0), nv = patch.num_points(1);
  TColgp_Array2OfPnt poles(1, nu, 1, nv);
  TColStd_Array2OfReal weights(1, nu, 1, nv);
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const auto& x = patch.control_point(patch.index(i, j));
      poles.SetValue(i + 1, j + 1, gp_Pnt(x.x(), x.y(), x.z()));
      weights.SetValue(i + 1, j + 1, patch.weight(patch.index(i, j)));
    }
  TColStd_Array1OfReal uk(1, 1), vk(1, 1);
  TColStd_Array1OfInteger um(1, 1), vm(1, 1);
  to_occt_knots(patch.knots(0), uk, um);
  to_occt_knots(patch.knots(1), vk, vm);
  return new Geom_BSplineSurface(poles, weights, uk, vk, um, vm, patch.degree(0), patch.degree(1));
}

Eigen::Vector3d vec(const gp_Pnt& p) {
  return {p.X(), p.Y(), p.Z()};
}
Eigen::Vector3d vec(const gp_Vec& v) {
  return {v.X(), v.Y(), v.Z()};
}

// Same knots (as a full vector), same control points and weights.
void expect_same_curve_data(const Patch& ours, const Handle(Geom_BSplineCurve) & theirs) {
  ASSERT_EQ(ours.num_points(), theirs->NbPoles());
  TColStd_Array1OfReal sequence(1, theirs->NbPoles() + theirs->Degree() + 1);
  theirs->KnotSequence(sequence);
  for (int i = 0; i < sequence.Length(); ++i)
    EXPECT_NEAR(ours.knots(0)[i], sequence(i + 1), kTolerance);
  for (int i = 0; i < ours.num_points(); ++i) {
    EXPECT_LT((ours.control_point(i) - vec(theirs->Pole(i + 1))).norm(), kTolerance);
    EXPECT_NEAR(ours.weight(i), theirs->Weight(i + 1), kTolerance);
  }
}

void expect_same_surface_data(const Patch& ours, const Handle(Geom_BSplineSurface) & theirs) {
  ASSERT_EQ(ours.num_points(0), theirs->NbUPoles());
  ASSERT_EQ(ours.num_points(1), theirs->NbVPoles());
  for (int j = 0; j < ours.num_points(1); ++j)
    for (int i = 0; i < ours.num_points(0); ++i) {
      const int index = ours.index(i, j);
      EXPECT_LT((ours.control_point(index) - vec(theirs->Pole(i + 1, j + 1))).norm(), kTolerance);
      EXPECT_NEAR(ours.weight(index), theirs->Weight(i + 1, j + 1), kTolerance);
    }
}

}  // namespace

TEST(OcctCrossCheck, CurveEvaluationAndFirstDerivative) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 40; ++trial) {
    const Patch curve = random_patch(rng, 1, 5, trial % 2 == 1, 4);
    const Handle(Geom_BSplineCurve) occt = to_occt_curve(curve);
    for (int q = 0; q < 50; ++q) {
      const Param u = random_param(rng, curve);
      gp_Pnt p;
      gp_Vec d1;
      occt->D1(u[0], p, d1);
      const PatchDerivatives ours = curve.derivatives(u, 1);
      EXPECT_LT((ours.point - vec(p)).norm(), kTolerance);
      EXPECT_LT((ours.first.col(0) - vec(d1)).norm(), kTolerance * (1 + d1.Magnitude()));
    }
  }
}

TEST(OcctCrossCheck, SurfaceEvaluationAndFirstDerivatives) {
  std::mt19937 rng(12);
  for (int trial = 0; trial < 30; ++trial) {
    const Patch surface = random_patch(rng, 2, 4, trial % 2 == 1, 3);
    const Handle(Geom_BSplineSurface) occt = to_occt_surface(surface);
    for (int q = 0; q < 50; ++q) {
      const Param u = random_param(rng, surface);
      gp_Pnt p;
      gp_Vec du, dv;
      occt->D1(u[0], u[1], p, du, dv);
      const PatchDerivatives ours = surface.derivatives(u, 1);
      EXPECT_LT((ours.point - vec(p)).norm(), kTolerance);
      EXPECT_LT((ours.first.col(0) - vec(du)).norm(), kTolerance * (1 + du.Magnitude()));
      EXPECT_LT((ours.first.col(1) - vec(dv)).norm(), kTolerance * (1 + dv.Magnitude()));
    }
  }
}

TEST(OcctCrossCheck, CurveKnotInsertionAndDegreeElevation) {
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> unit(0.02, 0.98);
  for (int trial = 0; trial < 30; ++trial) {
    const Patch curve = random_patch(rng, 1, 4, trial % 2 == 1, 3);
    // Single knot, several times.
    const double u = unit(rng);
    const int times = 1 + trial % curve.degree(0);
    Handle(Geom_BSplineCurve) occt = to_occt_curve(curve);
    occt->InsertKnot(u, times, 0.0, true);
    expect_same_curve_data(insert_knot(curve, 0, u, times), occt);
    // Many knots at once (InsertKnots takes distinct values with multiplicities).
    const double a = unit(rng), b = unit(rng);
    occt = to_occt_curve(curve);
    TColStd_Array1OfReal knots(1, 2);
    TColStd_Array1OfInteger mults(1, 2);
    knots.SetValue(1, std::min(a, b));
    knots.SetValue(2, std::max(a, b));
    mults.SetValue(1, 1);
    mults.SetValue(2, 1);
    occt->InsertKnots(knots, mults, 0.0, true);
    expect_same_curve_data(refine_knots(curve, 0, {a, b}), occt);
    // Degree elevation.
    const int raise = 1 + trial % 3;
    occt = to_occt_curve(curve);
    occt->IncreaseDegree(curve.degree(0) + raise);
    expect_same_curve_data(elevate_degree(curve, 0, raise), occt);
  }
}

TEST(OcctCrossCheck, SurfaceKnotInsertionAndDegreeElevation) {
  std::mt19937 rng(14);
  std::uniform_real_distribution<double> unit(0.02, 0.98);
  for (int trial = 0; trial < 20; ++trial) {
    const Patch surface = random_patch(rng, 2, 4, trial % 2 == 1, 2);
    const double u = unit(rng), v = unit(rng);
    Handle(Geom_BSplineSurface) occt = to_occt_surface(surface);
    occt->InsertUKnot(u, 1, 0.0, true);
    occt->InsertVKnot(v, 1, 0.0, true);
    expect_same_surface_data(insert_knot(insert_knot(surface, 0, u), 1, v), occt);
    occt = to_occt_surface(surface);
    occt->IncreaseDegree(surface.degree(0) + 1, surface.degree(1) + 2);
    expect_same_surface_data(elevate_degree(elevate_degree(surface, 0, 1), 1, 2), occt);
  }
}
