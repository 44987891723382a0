// IGA elasticity throughput: unit cube (p = 2, 3; n^3 elements) and a 2D square (256^2):
// assembly, factorisation + solve, DOFs per second and peak memory (getrusage).
// Factorisation alone of the clamped p = 2 cube's stiffness: CHOLMOD supernodal (what `analyze`
// uses; its speed is that of the BLAS loaded, reported as the `blas` label: run the program once
// as is and once with LD_LIBRARY_PATH=/usr/lib/x86_64-linux-gnu/openblas-pthread to compare) and
// Eigen's SimplicialLDLT (no BLAS), the alternative a user would pick. Wall and process CPU time.
// Iterative solves of the same system to ||b - K u|| / ||b|| < 1e-10 (BM_Iterative*): the
// incomplete-Cholesky CG `--solver cg` used before, Eigen's default (Jacobi) CG on the upper
// triangle and on both triangles, and block_cg.hpp's Jacobi and block-Jacobi CG (what
// `--solver cg` uses now), each with its difference from CHOLMOD's answer. The side-by-side
// table of docs/performance.md is one run of
//   bench_analysis --benchmark_filter='BM_(FactorCholmod|FactorEigenLDLT|Iterative[A-Za-z]*)/16/'
// and one with /32 (without FactorEigenLDLT: hours); 32^3 needs about 5 GB and minutes.
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <Eigen/CholmodSupport>
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>
#include <chrono>
#include <ctime>
#include <map>
#include <memory>

#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/blas_runtime.hpp"
#include "isospring/analysis/block_cg.hpp"
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
// CHOLMOD's fill-reducing ordering: arg 1 = 0 its default (AMD, then METIS too when
// AMD's factor is dense, keeping the better), 1 AMD only, 2 METIS only, 3 NESDIS only (CHOLMOD's
// nested dissection on METIS's partitioner). Counters: nonzeros and flops of the factor.
void BM_FactorCholmodOrdering(benchmark::State& state) {
  const Eigen::SparseMatrix<double> matrix = free_stiffness(static_cast<int>(state.range(0)));
  const int variant = static_cast<int>(state.range(1));
  double analyse_wall = 0, lnz = 0, flops = 0;
  int selected = -1;
  for (auto _ : state) {
    Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Upper> solver;
    cholmod_common& common = solver.cholmod();
    if (variant > 0) {
      common.nmethods = 1;
      common.method[0].ordering = variant == 1   ? CHOLMOD_AMD
                                  : variant == 2 ? CHOLMOD_METIS
                                                 : CHOLMOD_NESDIS;
      common.postorder = 1;
    }
    const auto wall = std::chrono::steady_clock::now();
    solver.analyzePattern(matrix);
    analyse_wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall).count();
    solver.factorize(matrix);
    if (solver.info() != Eigen::Success) state.SkipWithError("factorisation failed");
    lnz = common.lnz;
    flops = common.fl;
    selected = common.method[common.selected].ordering;
  }
  state.counters["analyse_s"] = analyse_wall;
  state.counters["factor_nnz"] = lnz;
  state.counters["flops"] = flops;
  state.counters["ordering"] = selected;  // CHOLMOD_AMD 2, METIS 3, NESDIS 4
  state.counters["dofs"] = static_cast<double>(matrix.rows());
  state.counters["peak_MB"] = peak_memory_mb();
}
void BM_FactorEigenLDLT(benchmark::State& state) {
  factorise<Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Upper>>(state);
}

// ---- Iterative solvers on the same system: time to reach ||b - K u|| / ||b|| < 1e-10
// from u = 0, the right-hand side of the unit traction. `diff_vs_direct` is
// ||u - u_cholmod|| / ||u_cholmod||, the CHOLMOD solution computed once per size (not timed).

struct IterativeCase {
  Eigen::SparseMatrix<double> upper;   // free DOFs, upper triangle
  Eigen::VectorXd rhs;                 // free DOFs
  Eigen::SparseMatrix<double> global;  // all DOFs, upper triangle
  std::vector<bool> fixed;             // global DOF is clamped
  Eigen::VectorXd global_rhs;          // 0 on clamped DOFs
  std::vector<int> free_dofs;
  Eigen::VectorXd direct;  // CHOLMOD's free solution
};

const IterativeCase& iterative_case(int n) {
  static std::map<int, IterativeCase> cases;
  auto found = cases.find(n);
  if (found != cases.end()) return found->second;
  IterativeCase& c = cases[n];
  const analysis::Problem problem = box_problem(3, 2, n);
  const analysis::DofMap dofs(problem);
  const analysis::Constraints constraints = analysis::build_constraints(problem, dofs);
  c.global = analysis::assemble_stiffness(problem, dofs);
  c.upper = free_stiffness(n);
  c.fixed.assign(static_cast<size_t>(c.global.rows()), false);
  for (int d : constraints.dofs) c.fixed[static_cast<size_t>(d)] = true;
  c.global_rhs = analysis::assemble_load(problem, dofs, problem.load_cases[0]);
  for (Eigen::Index k = 0; k < c.global_rhs.size(); ++k)
    if (c.fixed[static_cast<size_t>(k)])
      c.global_rhs[k] = 0;
    else
      c.free_dofs.push_back(static_cast<int>(k));
  c.rhs.resize(static_cast<Eigen::Index>(c.free_dofs.size()));
  for (size_t k = 0; k < c.free_dofs.size(); ++k)
    c.rhs[static_cast<Eigen::Index>(k)] = c.global_rhs[c.free_dofs[k]];
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Upper> cholesky(c.upper);
  c.direct = cholesky.solve(c.rhs);
  return c;
}

// Wall and process CPU seconds of `work`.
template <class Work>
std::pair<double, double> timed(Work&& work) {
  const auto wall = std::chrono::steady_clock::now();
  const std::clock_t cpu = std::clock();
  work();
  return {std::chrono::duration<double>(std::chrono::steady_clock::now() - wall).count(),
          static_cast<double>(std::clock() - cpu) / CLOCKS_PER_SEC};
}

void iterative_counters(benchmark::State& state, const IterativeCase& c,
                        const Eigen::VectorXd& solution, int iterations,
                        std::pair<double, double> setup, std::pair<double, double> solve) {
  state.counters["dofs"] = static_cast<double>(c.rhs.size());
  state.counters["iterations"] = iterations;
  state.counters["setup_s"] = setup.first;
  state.counters["setup_cpu_s"] = setup.second;
  state.counters["solve_s"] = solve.first;
  state.counters["solve_cpu_s"] = solve.second;
  state.counters["diff_vs_direct"] = (solution - c.direct).norm() / c.direct.norm();
  state.counters["residual"] =
      (c.rhs - c.upper.selfadjointView<Eigen::Upper>() * solution).norm() / c.rhs.norm();
  state.counters["peak_MB"] = peak_memory_mb();
}

constexpr double kTolerance = 1e-10;

template <class Solver>
void eigen_cg(benchmark::State& state, const Eigen::SparseMatrix<double>& matrix,
              const IterativeCase& c) {
  Eigen::VectorXd solution;
  std::pair<double, double> setup, solve;
  int iterations = 0;
  for (auto _ : state) {
    Solver solver;
    solver.setTolerance(kTolerance);
    solver.setMaxIterations(100000);
    setup = timed([&] { solver.compute(matrix); });
    solve = timed([&] { solution = solver.solve(c.rhs); });
    if (solver.info() != Eigen::Success) state.SkipWithError("CG did not converge");
    iterations = static_cast<int>(solver.iterations());
  }
  iterative_counters(state, c, solution, iterations, setup, solve);
}

// What `--solver cg` used before: incomplete Cholesky, upper triangle.
void BM_IterativeEigenIC(benchmark::State& state) {
  const IterativeCase& c = iterative_case(static_cast<int>(state.range(0)));
  eigen_cg<Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Upper,
                                    Eigen::IncompleteCholesky<double, Eigen::Upper>>>(state,
                                                                                      c.upper, c);
}
// Eigen's default: diagonal (Jacobi) preconditioner, upper triangle (one-thread product).
void BM_IterativeEigenJacobi(benchmark::State& state) {
  const IterativeCase& c = iterative_case(static_cast<int>(state.range(0)));
  eigen_cg<Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Upper>>(state, c.upper, c);
}
// Eigen's default on both triangles, row-major: the product runs on all OpenMP threads.
void BM_IterativeEigenJacobiFull(benchmark::State& state) {
  const IterativeCase& c = iterative_case(static_cast<int>(state.range(0)));
  const Eigen::SparseMatrix<double, Eigen::RowMajor> full = c.upper.selfadjointView<Eigen::Upper>();
  eigen_cg<Eigen::ConjugateGradient<Eigen::SparseMatrix<double, Eigen::RowMajor>,
                                    Eigen::Lower | Eigen::Upper>>(state, full, c);
}

void block(benchmark::State& state, analysis::BlockCgOptions::Preconditioner preconditioner) {
  const IterativeCase& c = iterative_case(static_cast<int>(state.range(0)));
  Eigen::VectorXd solution;
  std::pair<double, double> setup, solve;
  analysis::BlockCgResult out;
  for (auto _ : state) {
    std::unique_ptr<analysis::SymmetricBlockMatrix> matrix;
    setup = timed(
        [&] { matrix = std::make_unique<analysis::SymmetricBlockMatrix>(c.global, 3, c.fixed); });
    analysis::BlockCgOptions options;
    options.preconditioner = preconditioner;
    options.tolerance = kTolerance;
    Eigen::VectorXd global;
    solve = timed([&] { out = analysis::block_cg(*matrix, c.global_rhs, global, options); });
    if (!out.converged) state.SkipWithError("CG did not converge");
    solution.resize(c.rhs.size());
    for (size_t k = 0; k < c.free_dofs.size(); ++k)
      solution[static_cast<Eigen::Index>(k)] = global[c.free_dofs[k]];
  }
  iterative_counters(state, c, solution, out.iterations, setup, solve);
}
void BM_IterativeJacobi(benchmark::State& state) {
  block(state, analysis::BlockCgOptions::Preconditioner::kJacobi);
}
void BM_IterativeBlockJacobi(benchmark::State& state) {
  block(state, analysis::BlockCgOptions::Preconditioner::kBlockJacobi);
}

#define ISOSPRING_ITERATIVE(name) \
  BENCHMARK(name)                 \
      ->Arg(16)                   \
      ->Arg(32)                   \
      ->Unit(benchmark::kSecond)  \
      ->Iterations(1)             \
      ->MeasureProcessCPUTime()   \
      ->UseRealTime()
ISOSPRING_ITERATIVE(BM_IterativeEigenIC);
ISOSPRING_ITERATIVE(BM_IterativeEigenJacobi);
ISOSPRING_ITERATIVE(BM_IterativeEigenJacobiFull);
ISOSPRING_ITERATIVE(BM_IterativeJacobi);
ISOSPRING_ITERATIVE(BM_IterativeBlockJacobi);

BENCHMARK(BM_FactorCholmod)
    ->Arg(16)
    ->Arg(32)
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->MeasureProcessCPUTime()
    ->UseRealTime();
BENCHMARK(BM_FactorCholmodOrdering)
    ->ArgsProduct({{16, 32}, {0, 1, 2, 3}})
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
