// NURBS kernel throughput: batch evaluation of points plus first derivatives on a degree-3
// surface with 50 x 50 control points at 10^6 random parameters, isospring against
// OpenCascade's Geom_BSplineSurface::D1 on the same parameters (both single-threaded).
// Target: at least 2x OpenCascade's throughput.
#include <benchmark/benchmark.h>

#include <Geom_BSplineSurface.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColStd_Array2OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <random>

#include "isospring/nurbs/batch_evaluation.hpp"
#include "isospring/nurbs/refine.hpp"

namespace {
using namespace isospring::nurbs;

constexpr int kPoints = 1'000'000;

Patch make_surface(bool rational) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> noise(-0.2, 0.2), weight(0.5, 1.5);
  const KnotVector kv = KnotVector::uniform(3, 47);  // 47 spans + 3 = 50 control points
  std::vector<Eigen::Vector3d> points;
  std::vector<double> weights;
  for (int j = 0; j < 50; ++j)
    for (int i = 0; i < 50; ++i) {
      points.emplace_back(i + noise(rng), j + noise(rng), noise(rng));
      weights.push_back(rational ? weight(rng) : 1.0);
    }
  return Patch({kv, kv}, points, weights);
}

std::vector<Param> random_params() {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Param> params(kPoints);
  for (auto& u : params) u = {unit(rng), unit(rng), 0.0};
  return params;
}

Handle(Geom_BSplineSurface) to_occt(const Patch& patch) {
  const int n = 50;
  TColgp_Array2OfPnt poles(1, n, 1, n);
  TColStd_Array2OfReal weights(1, n, 1, n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const auto& x = patch.control_point(patch.index(i, j));
      poles.SetValue(i + 1, j + 1, gp_Pnt(x.x(), x.y(), x.z()));
      weights.SetValue(i + 1, j + 1, patch.weight(patch.index(i, j)));
    }
  const auto unique = patch.knots(0).unique();
  const auto mults = patch.knots(0).multiplicities();
  TColStd_Array1OfReal knots(1, static_cast<int>(unique.size()));
  TColStd_Array1OfInteger m(1, static_cast<int>(unique.size()));
  for (size_t i = 0; i < unique.size(); ++i) {
    knots.SetValue(static_cast<int>(i) + 1, unique[i]);
    m.SetValue(static_cast<int>(i) + 1, mults[i]);
  }
  if (patch.is_rational()) return new Geom_BSplineSurface(poles, weights, knots, knots, m, m, 3, 3);
  return new Geom_BSplineSurface(poles, knots, knots, m, m, 3, 3);
}

void BM_IsospringBatchD1(benchmark::State& state) {
  const Patch patch = make_surface(state.range(0) == 1);
  const std::vector<Param> params = random_params();
  const BatchEvaluator evaluator(patch);
  Eigen::Matrix3Xd points, first;
  for (auto _ : state) {
    evaluator.evaluate(params, points, &first);
    benchmark::DoNotOptimize(points.data());
    benchmark::DoNotOptimize(first.data());
  }
  state.SetItemsProcessed(state.iterations() * kPoints);
}

void BM_OpenCascadeD1(benchmark::State& state) {
  const Handle(Geom_BSplineSurface) surface = to_occt(make_surface(state.range(0) == 1));
  const std::vector<Param> params = random_params();
  Eigen::Matrix3Xd points(3, kPoints), first(3, 2 * kPoints);
  for (auto _ : state) {
    for (int q = 0; q < kPoints; ++q) {
      gp_Pnt p;
      gp_Vec du, dv;
      surface->D1(params[static_cast<size_t>(q)][0], params[static_cast<size_t>(q)][1], p, du, dv);
      points.col(q) << p.X(), p.Y(), p.Z();
      first.col(2 * q) << du.X(), du.Y(), du.Z();
      first.col(2 * q + 1) << dv.X(), dv.Y(), dv.Z();
    }
    benchmark::DoNotOptimize(points.data());
    benchmark::DoNotOptimize(first.data());
  }
  state.SetItemsProcessed(state.iterations() * kPoints);
}

// Argument: 0 = polynomial B-spline, 1 = rational (NURBS).
BENCHMARK(BM_IsospringBatchD1)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_OpenCascadeD1)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
