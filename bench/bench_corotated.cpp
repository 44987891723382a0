// Steps per second of the linear and the corotated reduced spring model
// (analysis/spring_reduced_model.hpp, spring_reduced_corotated.hpp) on cantilever lattices
// nx x 3 x 3 (nx = 10: the beam of the large-rotation tests) and n^3 cubes, at one load.
// Figures in docs/reduced_model.md.
#include <benchmark/benchmark.h>

#include <cmath>

#include "isospring/analysis/spring_mechanics.hpp"
#include "isospring/analysis/spring_reduced_corotated.hpp"

namespace isospring {
namespace {

// nx x ny x nz particles at unit spacing, 13 forward neighbours each (edges, face and body
// diagonals), stiffness 1000 L0, masses 1e-3, face x = 0 fixed, 5 % damping.
analysis::SpringNetwork box(int nx, int ny, int nz) {
  analysis::SpringNetwork net;
  auto index = [nx, ny](int i, int j, int l) { return (l * ny + j) * nx + i; };
  for (int l = 0; l < nz; ++l)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        net.positions.emplace_back(i, j, l);
        net.masses.push_back(1e-3);
        net.fixed.push_back(i == 0);
      }
  for (int l = 0; l < nz; ++l)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        for (int dl = 0; dl <= 1; ++dl)
          for (int dj = -1; dj <= 1; ++dj)
            for (int di = -1; di <= 1; ++di) {
              const bool forward = dl > 0 || dj > 0 || (dj == 0 && di > 0);
              const int a = i + di, b = j + dj, c = l + dl;
              if (!forward || a < 0 || b < 0 || a >= nx || b >= ny || c >= nz) continue;
              analysis::Spring s;
              s.i = index(i, j, l);
              s.j = index(a, b, c);
              s.rest_length = std::sqrt(static_cast<double>(di * di + dj * dj + dl * dl));
              s.stiffness = 1000.0 * s.rest_length;
              net.springs.push_back(s);
            }
  analysis::assign_damping_ratio(net, 0.05);
  return net;
}

// -y on every particle of the far face.
Eigen::VectorXd tip_load(const analysis::SpringNetwork& net, int nx) {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(net.positions.size()) * 3);
  for (size_t q = 0; q < net.positions.size(); ++q)
    if (net.positions[q].x() > nx - 1.5) f[static_cast<Eigen::Index>(q) * 3 + 1] = -1.0;
  return f;
}

// Arg 0: particles along x; arg 1: particles across (3: the beam; = nx: a cube).
void reduced_step(benchmark::State& state, bool corotated, int iterations = 1) {
  const int nx = static_cast<int>(state.range(0)), ny = static_cast<int>(state.range(1));
  const analysis::SpringNetwork net = box(nx, ny, ny);
  const Eigen::VectorXd load = tip_load(net, nx);
  analysis::CorotatedReducedModel model(net, 1e-3, {{24, {load}}, 6});
  model.set_iterations(iterations);
  analysis::ReducedSpringModel linear = model.linear();
  const Eigen::VectorXd g = 10.0 * linear.reduce_force(load);
  for (auto _ : state) {
    if (corotated) {
      model.step(g);
      benchmark::DoNotOptimize(model.coordinates().data());
    } else {
      linear.step(g);
      benchmark::DoNotOptimize(linear.coordinates().data());
    }
  }
  state.counters["particles"] = static_cast<double>(net.positions.size());
  state.counters["basis"] = model.size();
  state.counters["steps_per_s"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void BM_ReducedLinearStep(benchmark::State& state) {
  reduced_step(state, false);
}
void BM_ReducedCorotatedStep(benchmark::State& state) {
  reduced_step(state, true);
}
// Three force evaluations a step (two chord iterations of backward Euler).
void BM_ReducedCorotatedStep3(benchmark::State& state) {
  reduced_step(state, true, 3);
}
BENCHMARK(BM_ReducedLinearStep)->Args({10, 3})->Args({10, 10})->Args({22, 22});
BENCHMARK(BM_ReducedCorotatedStep)->Args({10, 3})->Args({10, 10})->Args({22, 22});
BENCHMARK(BM_ReducedCorotatedStep3)->Args({10, 3})->Args({10, 10});

}  // namespace
}  // namespace isospring

BENCHMARK_MAIN();
