// B-bar against the displacement formulation on the identify suite's 3D cantilever (a box
// 0.1 x 0.02 x 0.02 m clamped at x = 0, degree p = 2, 3, 4, 20 x 4 x 4 elements, nu = 0.49):
// stiffness entries (upper triangle), assembly, factorisation and solve seconds of one static
// solve. The B-bar stiffness couples DOFs through the projection's supports, so it has more entries
// per row; what it buys is fewer DOFs for the same accuracy (docs/verification.md).
//   bench_bbar --benchmark_filter='BM_Cantilever'
#include <benchmark/benchmark.h>

#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/static_solver.hpp"
#include "isospring/nurbs/refine.hpp"

namespace {

using namespace isospring;

analysis::Problem cantilever(int p, int k, analysis::Volumetric volumetric) {
  const nurbs::KnotVector linear(1, {0, 0, 1, 1});
  std::vector<Eigen::Vector3d> corners;
  for (int z = 0; z < 2; ++z)
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 2; ++x) corners.emplace_back(x * 0.1, y * 0.02, z * 0.02);
  analysis::Problem problem;
  problem.formulation = analysis::Formulation::kSolid;
  problem.volumetric = volumetric;
  problem.material = {7.5e6, 0.49, 1000.0, 1.0};
  problem.patches.push_back(
      nurbs::k_refine(nurbs::Patch({linear, linear, linear}, corners), {p, p, p}, {5 * k, k, k}));
  analysis::Support clamp;
  clamp.side = {0, 0, 0};
  clamp.fixed = {true, true, true};
  problem.supports.push_back(clamp);
  analysis::LoadCase load;
  load.id = "tip_down";
  load.tractions.push_back({{0, 0, 1}, {0, 0, -2000}, {}});
  problem.load_cases.push_back(load);
  return problem;
}

// Arguments: degree, k, volumetric (0 displacement, 1 B-bar).
void BM_Cantilever(benchmark::State& state) {
  const auto volumetric =
      state.range(2) ? analysis::Volumetric::kBbar : analysis::Volumetric::kDisplacement;
  const analysis::Problem problem =
      cantilever(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)), volumetric);
  analysis::StaticResult result;
  for (auto _ : state) {
    result = analysis::solve_static(problem);
    benchmark::DoNotOptimize(result.load_cases[0].max_displacement);
  }
  const analysis::DofMap dofs(problem);
  state.counters["dofs"] = result.dofs;
  state.counters["entries"] =
      static_cast<double>(analysis::assemble_stiffness(problem, dofs).nonZeros());
  state.counters["assembly_s"] = result.assembly_seconds;
  state.counters["factor_s"] = result.factorization_seconds;
  state.counters["solve_s"] = result.load_cases[0].solve_seconds;
}

}  // namespace

BENCHMARK(BM_Cantilever)
    ->Args({2, 4, 0})
    ->Args({2, 4, 1})
    ->Args({3, 4, 0})
    ->Args({3, 4, 1})
    ->Args({4, 4, 0})
    ->Args({4, 4, 1})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

BENCHMARK_MAIN();
