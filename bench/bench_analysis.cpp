// IGA elasticity throughput: unit cube (p = 2, 3; n^3 elements) and a 2D square (256^2):
// assembly, factorisation + solve, DOFs per second and peak memory (getrusage).
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/static_solver.hpp"
#include "isospring/nurbs/refine.hpp"

namespace {

using namespace isospring;

nurbs::Patch unit_box(int dim, int degree, int n) {
  const nurbs::KnotVector linear(1, {0, 0, 1, 1});
  std::vector<Eigen::Vector3d> points;
  for (int k = 0; k < (dim == 3 ? 2 : 1); ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) points.emplace_back(i, j, k);
  nurbs::Patch box(dim == 3 ? std::vector{linear, linear, linear} : std::vector{linear, linear},
                   points);
  return nurbs::k_refine(box, {degree, degree, dim == 3 ? degree : 0}, {n, n, dim == 3 ? n : 1});
}

// Clamped at x = 0, unit traction on x = 1.
analysis::Problem box_problem(int dim, int degree, int n) {
  analysis::Problem problem;
  problem.formulation =
      dim == 3 ? analysis::Formulation::kSolid : analysis::Formulation::kPlaneStress;
  problem.material = {210e9, 0.3, 7800, 1.0};
  problem.patches.push_back(unit_box(dim, degree, n));
  analysis::Support clamp;
  clamp.side = {0, 0, 0};
  clamp.fixed = {true, true, true};
  problem.supports.push_back(clamp);
  analysis::LoadCase load;
  load.id = "tension";
  load.tractions.push_back({{0, 0, 1}, {1e6, 0, 0}, {}});
  problem.load_cases.push_back(load);
  return problem;
}

double peak_memory_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // kB on Linux
}

void solve(benchmark::State& state, int dim) {
  const int degree = static_cast<int>(state.range(0)), n = static_cast<int>(state.range(1));
  const analysis::Problem problem = box_problem(dim, degree, n);
  analysis::StaticResult result;
  for (auto _ : state) {
    result = analysis::solve_static(problem);
    benchmark::DoNotOptimize(result.load_cases[0].max_displacement);
  }
  state.counters["dofs"] = result.dofs;
  state.counters["assembly_s"] = result.assembly_seconds;
  state.counters["factor_s"] = result.factorization_seconds;
  state.counters["solve_s"] = result.load_cases[0].solve_seconds;
  state.counters["assembly_dofs_per_s"] = result.dofs / result.assembly_seconds;
  state.counters["peak_MB"] = peak_memory_mb();
}

void BM_Cube(benchmark::State& state) {
  solve(state, 3);
}
void BM_Square(benchmark::State& state) {
  solve(state, 2);
}

BENCHMARK(BM_Cube)
    ->ArgsProduct({{2, 3}, {8, 16, 32}})
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->UseRealTime();
BENCHMARK(BM_Square)
    ->Args({2, 256})
    ->Args({3, 256})
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
