// NMSM speed: calibration time (cube n^3, grouped and per spring), linear static solves with a
// prefactorised stiffness, and explicit (velocity Verlet) / implicit (backward Euler: Newton, and
// linearly implicit with a prefactorised matrix) step rates.
// Targets: cube 6^3 grouped fit < 0.1 s, per spring < 2 s. The machine may be shared:
// compare CPU times and the last_fit_cpu_s counter (process CPU of the fit alone), not wall time.
// Direct solves at 10^5 particles (300k DOFs, 27-point 3D stencil) need minutes and GBs for the
// factorisation, so the 10^5 rows cover the explicit step only.
//
// Measured 2026-11-23 (2 shared cores, load ~2-3; old = the code before, run alternately with
// the new, CPU times):
//   fit (last_fit_cpu_s)       old      new     notes
//   cube 6^3 grouped           0.046 s  0.046 s  Ceres, 17 iterations, e_rms 2.775 % (0.09-0.1
//                                                 s for both under heavier load)
//   cube 6^3 per spring        2.6-3.0  2.0-2.1  s; dual LM, 47 iterations, e_rms 0.1542 % both
//   cube 12^3 grouped          -        3.2 s    (unchanged code path; 14 iterations)
//   cube 20^3 grouped          -        41 s     (unchanged code path; 23 iterations)
//   steps / s (CPU)            old      new
//   Verlet 10^3 / 10^4         8.5-9.2k / 530-550  10.1k / 620-650
//   Verlet 10^5                19-25            22-23  (run-to-run noise: no change claimed)
//   linear implicit 10^3/10^4  1.25k / 25.2      1.32k / 25.6  (the CHOLMOD solve dominates)
//   backward Euler 10^3        8.2               8.6
//   static solve 10^3 / 10^4   1650 / 30 (CHOLMOD), 1200 / 9 (Eigen LDL^T): unchanged
// Per spring, where the time went (6^3, per LM iteration, before): the Jacobian's K^-1 (one
// solve with 540 right-hand sides) ~19 ms, gram()'s K^-1 (G K^-1) (another) ~18 ms, the
// 540 x 540 Cholesky ~7 ms (~13 ms with two OpenMP threads), 10 MB Jacobian copies and
// reallocations ~6 ms. Now: the K form (fitting/src/nmsm/dual_levenberg_marquardt.hpp) replaces
// gram() by a K^2 + G assembled in O(springs) (~5 ms), one thread, no copies. What remains is
// the Jacobian's K^-1 and the Cholesky; below 2 s would need the dual step without a dense J.
// Verlet, before: two passes over the springs per force (spring, damping) and five 256 KB
// temporaries per step at 10^4 (page faults); now one fused pass, no allocation. Each spring
// costs ~16 cycles (a sqrt, a division and 6 scattered read-modify-writes); SSE2 blocks for the
// sqrt/division and register accumulation of the first particle did not help (measured), so
// 1000 steps/s at 10^4 needs AVX or threads (not bit-for-bit: the sums reorder).
#include <benchmark/benchmark.h>

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCholesky>
#include <chrono>
#include <cmath>

#include "isospring/analysis/spring_dynamics.hpp"
#include "isospring/analysis/spring_linear_implicit.hpp"
#include "isospring/analysis/spring_mechanics.hpp"
#include "isospring/analysis/spring_reduced_model.hpp"
#include "isospring/analysis/spring_static.hpp"
#include "isospring/fitting/calibration.hpp"
#include "isospring/fitting/spring_masses.hpp"
#include "isospring/fitting/thesis_experiments.hpp"

namespace {

using namespace isospring;

// Calibration of the [S15] cube with an n^3 net; the counter is the fit alone (no IGA solve).
void calibrate_cube(benchmark::State& state, bool per_spring) {
  const fitting::ThesisObject cube = fitting::thesis_cube(static_cast<int>(state.range(0)), 2);
  fitting::CalibrationSettings settings;
  settings.fit_cases = {"fit_points"};
  settings.per_spring = per_spring;
  settings.regularization = per_spring ? 1e-7 : 0.0;
  double fit_seconds = 0;
  for (auto _ : state) {
    const fitting::CalibrationResult result = fitting::calibrate(cube.problem, settings);
    fit_seconds = result.fit_seconds;
    state.counters["parameters"] = result.parameters;
    state.counters["e_rms"] = result.fit[0].control.percent_e_rms;
    state.counters["lm_iterations"] = result.fit_result.iterations;
    state.counters["last_fit_cpu_s"] = result.fit_result.cpu_seconds;
  }
  state.counters["fit_seconds"] = fit_seconds;
}
void BM_CalibrateCubeGrouped(benchmark::State& state) {
  calibrate_cube(state, false);
}
void BM_CalibrateCubePerSpring(benchmark::State& state) {
  calibrate_cube(state, true);
}
BENCHMARK(BM_CalibrateCubeGrouped)->Arg(6)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CalibrateCubeGrouped)->Arg(12)->Arg(20)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CalibrateCubePerSpring)->Arg(6)->Iterations(1)->Unit(benchmark::kMillisecond);

// A cube lattice of n^3 particles (unit spacing, edge/face/body springs of the NMSM topology),
// face x = 0 fixed, stiffness 1000 L0 and unit masses.
// Built directly (the NMSM topology of a regular net: every particle to its 13 forward
// neighbours, i.e. cell edges, face diagonals and body diagonals once each; n = 6 gives the
// published 1940): building it through thesis_cube + build_spring_mesh takes minutes and GBs at
// 46^3 = 10^5 particles.
analysis::SpringNetwork lattice(int n) {
  analysis::SpringNetwork net;
  auto index = [n](int i, int j, int k) { return (k * n + j) * n + i; };
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        net.positions.emplace_back(i, j, k);
        net.masses.push_back(1.0);
        net.fixed.push_back(i == 0);
      }
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        for (int dk = -1; dk <= 1; ++dk)
          for (int dj = -1; dj <= 1; ++dj)
            for (int di = -1; di <= 1; ++di) {
              // Forward half of the 26 neighbours: first non-zero offset positive.
              const bool forward = dk > 0 || (dk == 0 && (dj > 0 || (dj == 0 && di > 0)));
              const int a = i + di, b = j + dj, c = k + dk;
              if (!forward || a < 0 || b < 0 || c < 0 || a >= n || b >= n || c >= n) continue;
              analysis::Spring s;
              s.i = index(i, j, k);
              s.j = index(a, b, c);
              s.rest_length = std::sqrt(static_cast<double>(di * di + dj * dj + dk * dk));
              s.stiffness = 1000.0 * s.rest_length;
              net.springs.push_back(s);
            }
  return net;
}

int side_for(int particles) {
  return static_cast<int>(std::lround(std::cbrt(particles)));
}

// Solves with a prefactorised rest stiffness: Eigen's simplicial LDL^T (AMD) against CHOLMOD's
// supernodal LL^T (its own ordering choice, BLAS-3 supernodes).
template <typename Solver>
void static_solves(benchmark::State& state) {
  const analysis::SpringNetwork net = lattice(side_for(static_cast<int>(state.range(0))));
  const int dofs = static_cast<int>(net.positions.size()) * 3;
  const analysis::FreeDofSet free(dofs, analysis::constrained_dofs(net, {}));
  Solver solver(free.restrict(analysis::rest_stiffness(net)));
  const Eigen::VectorXd f = Eigen::VectorXd::Ones(free.num_free());
  Eigen::VectorXd u(f.size());
  for (auto _ : state) {
    u = solver.solve(f);  // assign: a bare solve() is a lazy expression that does no work
    benchmark::DoNotOptimize(u.data());
  }
  state.counters["particles"] = static_cast<double>(net.positions.size());
  state.counters["solves_per_s"] =
      benchmark::Counter(1, benchmark::Counter::kIsIterationInvariantRate);
}
void BM_StaticSolvePrefactorised(benchmark::State& state) {
  static_solves<Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>>(state);
}
void BM_StaticSolvePrefactorisedCholmod(benchmark::State& state) {
  static_solves<Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Upper>>(state);
}
BENCHMARK(BM_StaticSolvePrefactorised)->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StaticSolvePrefactorisedCholmod)->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond);

void BM_VerletStep(benchmark::State& state) {
  const analysis::SpringNetwork net = lattice(side_for(static_cast<int>(state.range(0))));
  analysis::SpringState s = analysis::rest_state(net);
  const Eigen::VectorXd f = Eigen::VectorXd::Constant(s.x.size(), 0.01);
  for (auto _ : state) analysis::step_velocity_verlet(net, s, f, 1e-4);
  state.counters["particles"] = static_cast<double>(net.positions.size());
  state.counters["steps_per_s"] =
      benchmark::Counter(1, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_VerletStep)
    ->Arg(1000)
    ->Arg(10000)
    ->Arg(100000)
    ->Arg(6 * 6 * 6)  // 1940 springs: the calibrated 6^3 cube's net
    ->Unit(benchmark::kMillisecond);

void BM_BackwardEulerStep(benchmark::State& state) {
  const analysis::SpringNetwork net = lattice(side_for(static_cast<int>(state.range(0))));
  analysis::SpringState s = analysis::rest_state(net);
  const Eigen::VectorXd f = Eigen::VectorXd::Constant(s.x.size(), 0.01);
  for (auto _ : state) analysis::step_backward_euler(net, s, f, 1e-3);
  state.counters["particles"] = static_cast<double>(net.positions.size());
  state.counters["steps_per_s"] =
      benchmark::Counter(1, benchmark::Counter::kIsIterationInvariantRate);
}
// Newton rebuilds and refactorises every iteration: 10^3 particles only.
BENCHMARK(BM_BackwardEulerStep)->Arg(1000)->Unit(benchmark::kMillisecond);

void BM_LinearImplicitStep(benchmark::State& state) {
  const analysis::SpringNetwork net = lattice(side_for(static_cast<int>(state.range(0))));
  analysis::SpringState s = analysis::rest_state(net);
  const Eigen::VectorXd f = Eigen::VectorXd::Constant(s.x.size(), 0.01);
  analysis::LinearImplicitIntegrator integrator(net, 1e-3);
  for (auto _ : state) integrator.step(s, f);
  state.counters["particles"] = static_cast<double>(net.positions.size());
  state.counters["steps_per_s"] =
      benchmark::Counter(1, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_LinearImplicitStep)->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond);

// The reduced model (analysis/spring_reduced_model.hpp) of the same lattices: 32 lowest modes
// plus the static shape of the load, stepped by the projected linearly implicit scheme.
// Haptic loop: a force on one particle in, that particle's displacement out (O(r) each, the
// step O(r^2)); "full field": every DOF's displacement as well, for rendering (O(n r)).
// Counters: the reduced model's error against the full LinearImplicitIntegrator over 200 steps
// of the same load (not at 10^5 particles: the full run alone takes minutes there).
analysis::ReducedSpringModel reduced_lattice_model(const analysis::SpringNetwork& net,
                                                   Eigen::VectorXd& load) {
  load = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(net.positions.size()) * 3);
  const int n = side_for(static_cast<int>(net.positions.size()));
  for (int k = 0; k < n; ++k)  // the far face x = n - 1 pushed along -y
    for (int j = 0; j < n; ++j) load[3 * ((k * n + j) * n + n - 1) + 1] = -0.01;
  return analysis::ReducedSpringModel(net, 1e-3, {32, {load}});
}

void reduced_steps(benchmark::State& state, bool full_field) {
  const analysis::SpringNetwork net = lattice(side_for(static_cast<int>(state.range(0))));
  Eigen::VectorXd load;
  const auto start = std::chrono::steady_clock::now();
  analysis::ReducedSpringModel model = reduced_lattice_model(net, load);
  state.counters["build_s"] =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (full_field && net.positions.size() <= 20000) {
    const analysis::ReductionError error = analysis::reduction_error(net, model, load, 200);
    state.counters["static_error"] = error.static_relative;
    state.counters["projection_error"] = error.projection_relative;
    state.counters["dynamic_error"] = error.dynamic_relative;
  }
  const int probe = static_cast<int>(net.positions.size()) - 1;  // a far corner
  Eigen::VectorXd field;
  for (auto _ : state) {
    model.step(model.reduce_particle_force(probe, Eigen::Vector3d(0.0, -0.01, 0.0)));
    Eigen::Vector3d u = model.particle_displacement(probe);
    benchmark::DoNotOptimize(u.data());
    if (full_field) {
      field = model.displacement();
      benchmark::DoNotOptimize(field.data());
    }
  }
  state.counters["particles"] = static_cast<double>(net.positions.size());
  state.counters["basis"] = model.size();
  state.counters["steps_per_s"] =
      benchmark::Counter(1, benchmark::Counter::kIsIterationInvariantRate);
}
void BM_ReducedStepHaptic(benchmark::State& state) {
  reduced_steps(state, false);
}
void BM_ReducedStepFullField(benchmark::State& state) {
  reduced_steps(state, true);
}
BENCHMARK(BM_ReducedStepHaptic)->Arg(1000)->Arg(10000)->Arg(100000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ReducedStepFullField)
    ->Arg(1000)
    ->Arg(10000)
    ->Arg(100000)
    ->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
