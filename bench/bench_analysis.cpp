// IGA elasticity throughput: unit cube (p = 2, 3; n^3 elements) and a 2D square (256^2):
// assembly, factorisation + solve, DOFs per second and peak memory (getrusage).
// Factorisation alone of the clamped p = 2 cube's stiffness: CHOLMOD supernodal (what `analyze`
// uses; its speed is that of the BLAS loaded, reported as the `blas` label: run the program once
// as is and once with LD_LIBRARY_PATH=/usr/lib/x86_64-linux-gnu/openblas-pthread to compare) and
// Eigen's SimplicialLDLT (no BLAS), the alternative a user would pick. Wall and process CPU time.
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCholesky>
#include <chrono>
#include <ctime>

#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/blas_runtime.hpp"
#include "isospring/analysis/constraints.hpp"
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

// The stiffness of box_problem(3, 2, n) restricted to its free DOFs (upper triangle).
Eigen::SparseMatrix<double> free_stiffness(int n) {
  const analysis::Problem problem = box_problem(3, 2, n);
  const analysis::DofMap dofs(problem);
  const analysis::Constraints constraints = analysis::build_constraints(problem, dofs);
  const Eigen::SparseMatrix<double> stiffness = analysis::assemble_stiffness(problem, dofs);
  std::vector<int> free_index(static_cast<size_t>(stiffness.rows()), 0);
  for (int d : constraints.dofs) free_index[static_cast<size_t>(d)] = -1;
  int free = 0;
  for (int& index : free_index)
    if (index == 0) index = free++;
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(static_cast<size_t>(stiffness.nonZeros()));
  for (int col = 0; col < stiffness.outerSize(); ++col)
    for (Eigen::SparseMatrix<double>::InnerIterator it(stiffness, col); it; ++it) {
      const int i = free_index[static_cast<size_t>(it.row())];
      const int j = free_index[static_cast<size_t>(it.col())];
      if (i >= 0 && j >= 0 && i <= j) entries.emplace_back(i, j, it.value());
    }
  Eigen::SparseMatrix<double> reduced(free, free);
  reduced.setFromTriplets(entries.begin(), entries.end());
  return reduced;
}

template <class Solver>
void factorise(benchmark::State& state) {
  const Eigen::SparseMatrix<double> matrix = free_stiffness(static_cast<int>(state.range(0)));
  double analyse_wall = 0, analyse_cpu = 0;
  for (auto _ : state) {
    Solver solver;
    // The symbolic analysis (fill-reducing ordering, elimination tree) and the numeric
    // factorisation separately: only the latter calls the BLAS.
    const auto wall = std::chrono::steady_clock::now();
    const std::clock_t cpu = std::clock();
    solver.analyzePattern(matrix);
    analyse_cpu = static_cast<double>(std::clock() - cpu) / CLOCKS_PER_SEC;
    analyse_wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall).count();
    solver.factorize(matrix);
    if (solver.info() != Eigen::Success) state.SkipWithError("factorisation failed");
    benchmark::ClobberMemory();
  }
  state.counters["analyse_s"] = analyse_wall;
  state.counters["analyse_cpu_s"] = analyse_cpu;
  const analysis::BlasRuntime blas = analysis::loaded_blas();
  state.SetLabel(blas.name + " " + blas.library);
  state.counters["dofs"] = static_cast<double>(matrix.rows());
  state.counters["peak_MB"] = peak_memory_mb();
}

void BM_FactorCholmod(benchmark::State& state) {
  factorise<Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Upper>>(state);
}
void BM_FactorEigenLDLT(benchmark::State& state) {
  factorise<Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Upper>>(state);
}

BENCHMARK(BM_FactorCholmod)
    ->Arg(16)
    ->Arg(32)
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->MeasureProcessCPUTime()
    ->UseRealTime();
BENCHMARK(BM_FactorEigenLDLT)
    ->Arg(16)
    ->Arg(24)
    ->Arg(32)
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

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
