// Immersed elasticity end to end on analytic shapes: the immersed domain (cell classification,
// line quadrature of cut cells, boundary points), the assembly (bulk, Nitsche with the per-cell
// eigenvalue penalty, ghost penalty) and the sparse Cholesky solve, separately.
//  - 2D: the Kirsch quarter plate with a hole, p = 3, 64 x 64 cells (~8,900 DOFs);
//  - 3D: the plate with a cylindrical hole extruded, p = 2, 16 x 16 x 4 cells (~6,000 DOFs).
#include <benchmark/benchmark.h>

#include "isospring/analysis/immersed.hpp"
#include "isospring/geometry/immersed_implicit.hpp"

namespace {
using namespace isospring;

geometry::ImplicitShape plate(int dimension) {
  geometry::ImplicitShape shape;
  shape.dimension = dimension;
  shape.box_max = {4, 4, 1};
  shape.circles.push_back({Eigen::Vector2d::Zero(), 1.0, false});
  return shape;
}

geometry::ImplicitGrid grid(int dimension) {
  geometry::ImplicitGrid g;
  g.degree = dimension == 2 ? 3 : 2;
  g.elements = dimension == 2 ? Eigen::Vector3i(64, 64, 1) : Eigen::Vector3i(16, 16, 4);
  return g;
}

analysis::ImmersedOptions options(int dimension) {
  analysis::ImmersedOptions o;
  o.formulation =
      dimension == 2 ? analysis::Formulation::kPlaneStress : analysis::Formulation::kSolid;
  o.material = {1e5, 0.3, 1.0, 1.0};
  for (int face : {0, 2}) {
    analysis::ImmersedSupport s;
    s.face = face;
    s.symmetry = true;
    o.supports.push_back(s);
  }
  if (dimension == 3) {
    analysis::ImmersedSupport s;
    s.face = 4;
    s.symmetry = true;
    o.supports.push_back(s);
  }
  analysis::ImmersedPressure p;
  p.face = 1;
  p.value = -10.0;
  o.pressures.push_back(p);
  return o;
}

void BM_ImmersedDomain(benchmark::State& state) {
  const int dimension = static_cast<int>(state.range(0));
  for (auto _ : state)
    benchmark::DoNotOptimize(geometry::immerse_implicit(plate(dimension), grid(dimension)));
}
BENCHMARK(BM_ImmersedDomain)->Arg(2)->Arg(3)->Unit(benchmark::kMillisecond);

void BM_ImmersedAssembly(benchmark::State& state) {
  const int dimension = static_cast<int>(state.range(0));
  const auto domain = geometry::immerse_implicit(plate(dimension), grid(dimension));
  const auto o = options(dimension);
  for (auto _ : state) benchmark::DoNotOptimize(analysis::assemble_immersed(domain, o));
}
BENCHMARK(BM_ImmersedAssembly)->Arg(2)->Arg(3)->Unit(benchmark::kMillisecond);

void BM_ImmersedSolve(benchmark::State& state) {
  const int dimension = static_cast<int>(state.range(0));
  const auto domain = geometry::immerse_implicit(plate(dimension), grid(dimension));
  const auto o = options(dimension);
  analysis::ImmersedResult result;
  for (auto _ : state) {
    result = analysis::solve_immersed(domain, o);
    benchmark::DoNotOptimize(result);
  }
  state.counters["dofs"] = result.dofs;
  state.counters["assembly_s"] = result.assembly_seconds;
  state.counters["solve_s"] = result.solve_seconds;
}
BENCHMARK(BM_ImmersedSolve)->Arg(2)->Arg(3)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
