// Cost per step of the engine runtime (runtime.h), one term kind at a time, at 10^3, 10^4 and
// 10^5 particles: an n^3 lattice (n = 10, 22, 46) of spacing 1 cm built with the C builder
// functions, evaluated at a perturbed, moving state. Per kind:
//   Springs       the NMSM topology: 12 edges, 12 face and 4 body diagonals per cell (13 per
//                 particle), with damping
//   CellVolume    one volume term per cell (trilinear det J at 8 Gauss points)
//   CellShear     one shear term per cell (mean Green strain over 8 corners)
//   CellArea2D    the membranes' cells: an n^2 sheet (n = 32, 100, 316) with one area term
//   CellShear2D   (bilinear det J at 4 Gauss points) or one shear term (4 corners) per cell
//   PointVolume   strain points of a degree-2 net: 1 Gauss point per knot span ("1") or the
//   PointShear    analysis' full rule, 3 per direction ("27"), each over 27 particles
//   Reduced       a reduced model of r = 32 / 64 basis vectors: the step (O(r^2)) plus the whole
//                 displacement field (O(n r)), what an engine renders each step
// Forces: isospring_model_forces; Jvp: isospring_model_force_jvp (elastic and damping parts).
// The full-rule strain points at 10^5 particles (2.3e6 points of 27 particles: 1.5 GB of
// gradients) are left out: beyond this machine's share of memory for a benchmark.
//
// Measured 2026-11-27 (2 shared cores, one thread, CPU time per call, microseconds):
// see the README ("Engine runtime") and the closing report.
#include <benchmark/benchmark.h>

#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <stdexcept>
#include <vector>

#include "isospring/runtime/runtime.h"

namespace {

constexpr double kSpacing = 0.01;

struct Lattice {
  int n = 0;
  std::vector<double> rest, masses;
  int index(int i, int j, int k) const { return i + n * (j + n * k); }
};

Lattice lattice(int n) {
  Lattice l;
  l.n = n;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        l.rest.insert(l.rest.end(), {kSpacing * i, kSpacing * j, kSpacing * k});
        l.masses.push_back(1e-3);
      }
  return l;
}

void check(int ok, const char* error) {
  if (!ok) throw std::runtime_error(error);
}

void add_springs(isospring_model* m, const Lattice& l) {
  std::vector<int> ends;
  std::vector<double> k, c, l0;
  const int n = l.n;
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x)
        for (int dz = -1; dz <= 1; ++dz)
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
              // Each pair once: the 13 neighbours with a positive first non-zero offset.
              const int key = dz * 9 + dy * 3 + dx;
              if (key <= 0) continue;
              const int a = x + dx, b = y + dy, cc = z + dz;
              if (a < 0 || b < 0 || cc < 0 || a >= n || b >= n || cc >= n) continue;
              ends.push_back(l.index(x, y, z));
              ends.push_back(l.index(a, b, cc));
              k.push_back(100.0);
              c.push_back(0.01);
              l0.push_back(kSpacing * std::sqrt(dx * dx + dy * dy + dz * dz));
            }
  char error[300];
  check(isospring_model_add_springs(m, k.size(), ends.data(), k.data(), c.data(), l0.data(), error,
                                    sizeof(error)),
        error);
}

void add_cells(isospring_model* m, const Lattice& l, int term) {
  std::vector<int> corners;
  std::vector<double> moduli, volumes;
  for (int z = 0; z + 1 < l.n; ++z)
    for (int y = 0; y + 1 < l.n; ++y)
      for (int x = 0; x + 1 < l.n; ++x) {
        for (int a = 0; a < 8; ++a)
          corners.push_back(l.index(x + (a & 1), y + ((a >> 1) & 1), z + ((a >> 2) & 1)));
        moduli.push_back(1e4);
        volumes.push_back(kSpacing * kSpacing * kSpacing);
      }
  char error[300];
  check(isospring_model_add_cells(m, term, moduli.size(), corners.data(), moduli.data(),
                                  volumes.data(), error, sizeof(error)),
        error);
}

// Uniform quadratic B-splines on a span [0, 1] and their derivatives.
std::array<double, 3> bspline(double t) {
  return {0.5 * (1 - t) * (1 - t), 0.5 * (-2 * t * t + 2 * t + 1), 0.5 * t * t};
}
std::array<double, 3> bspline_derivative(double t) {
  return {-(1 - t), 1 - 2 * t, t};
}

// Strain points of a uniform degree-2 net on the lattice (control points at the Greville
// points, so F = I at rest): `per_direction` Gauss points in each of the (n - 2)^3 spans.
void add_points(isospring_model* m, const Lattice& l, int term, int per_direction) {
  const double g = std::sqrt(0.6) / 2;
  const std::vector<double> ts =
      per_direction == 1 ? std::vector<double>{0.5} : std::vector<double>{0.5 - g, 0.5, 0.5 + g};
  std::vector<size_t> offsets{0};
  std::vector<int> particles;
  std::vector<double> gradients, moduli, volumes;
  for (int z = 0; z + 2 < l.n; ++z)
    for (int y = 0; y + 2 < l.n; ++y)
      for (int x = 0; x + 2 < l.n; ++x)
        for (double tz : ts)
          for (double ty : ts)
            for (double tx : ts) {
              const double t[3] = {tx, ty, tz};
              std::array<double, 3> b[3], d[3];
              for (int m3 = 0; m3 < 3; ++m3) {
                b[m3] = bspline(t[m3]);
                d[m3] = bspline_derivative(t[m3]);
              }
              for (int c = 0; c < 3; ++c)
                for (int bb = 0; bb < 3; ++bb)
                  for (int a = 0; a < 3; ++a) {
                    particles.push_back(l.index(x + a, y + bb, z + c));
                    const int idx[3] = {a, bb, c};
                    for (int dir = 0; dir < 3; ++dir) {
                      double value = d[dir][static_cast<size_t>(idx[dir])] / kSpacing;
                      for (int o = 0; o < 3; ++o)
                        if (o != dir) value *= b[o][static_cast<size_t>(idx[o])];
                      gradients.push_back(value);
                    }
                  }
              offsets.push_back(particles.size());
              moduli.push_back(1e4);
              volumes.push_back(std::pow(kSpacing, 3) / std::pow(per_direction, 3));
            }
  char error[300];
  check(isospring_model_add_points(m, term, moduli.size(), offsets.data(), particles.data(),
                                   gradients.data(), moduli.data(), volumes.data(), error,
                                   sizeof(error)),
        error);
}

enum Kind { kSprings, kCellVolume, kCellShear, kPointVolume, kPointShear };

using Handle = std::unique_ptr<isospring_model, void (*)(isospring_model*)>;

// An n^2 sheet of spacing 1 cm in the plane (2D model) with one area or shear term per cell.
Handle sheet_cells(int n, int term) {
  std::vector<double> rest, masses;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      rest.insert(rest.end(), {kSpacing * i, kSpacing * j});
      masses.push_back(1e-3);
    }
  char error[300];
  Handle m(isospring_model_create(2, masses.size(), rest.data(), masses.data(), nullptr, error,
                                  sizeof(error)),
           isospring_model_free);
  check(m != nullptr, error);
  std::vector<int> corners;
  std::vector<double> moduli, areas;
  for (int y = 0; y + 1 < n; ++y)
    for (int x = 0; x + 1 < n; ++x) {
      for (int a = 0; a < 4; ++a) corners.push_back((x + (a & 1)) + n * (y + ((a >> 1) & 1)));
      moduli.push_back(1e4);
      areas.push_back(kSpacing * kSpacing);
    }
  check(isospring_model_add_cells(m.get(), term, moduli.size(), corners.data(), moduli.data(),
                                  areas.data(), error, sizeof(error)),
        error);
  return m;
}

// One model per (kind, n, points), built once per process.
isospring_model* model_of(Kind kind, int n, int per_direction) {
  static std::map<std::array<int, 3>, Handle> cache;
  const std::array<int, 3> key{kind, n, per_direction};
  if (auto found = cache.find(key); found != cache.end()) return found->second.get();
  const Lattice l = lattice(n);
  char error[300];
  isospring_model* m = isospring_model_create(3, l.masses.size(), l.rest.data(), l.masses.data(),
                                              nullptr, error, sizeof(error));
  check(m != nullptr, error);
  switch (kind) {
    case kSprings:
      add_springs(m, l);
      break;
    case kCellVolume:
      add_cells(m, l, ISOSPRING_TERM_CELL_VOLUME);
      break;
    case kCellShear:
      add_cells(m, l, ISOSPRING_TERM_CELL_SHEAR);
      break;
    case kPointVolume:
      add_points(m, l, ISOSPRING_TERM_POINT_VOLUME, per_direction);
      break;
    case kPointShear:
      add_points(m, l, ISOSPRING_TERM_POINT_SHEAR, per_direction);
      break;
  }
  cache.emplace(key, Handle(m, isospring_model_free));
  return m;
}

// A deformed, moving state: 1% of the spacing, deterministic.
std::vector<double> state_of(const isospring_model* m, double amplitude, bool positions) {
  const size_t size = isospring_model_state_size(m);
  std::vector<double> x(size);
  const double* rest = isospring_model_rest_positions(m);
  for (size_t e = 0; e < size; ++e)
    x[e] = (positions ? rest[e] : 0.0) + amplitude * std::sin(0.37 * static_cast<double>(e));
  return x;
}

void run(benchmark::State& state, Kind kind, int per_direction, bool jvp) {
  const int n = static_cast<int>(state.range(0));
  isospring_model* m = model_of(kind, n, per_direction);
  const std::vector<double> x = state_of(m, 0.01 * kSpacing, true), v = state_of(m, 0.1, false);
  std::vector<double> out(x.size());
  for (auto _ : state) {
    if (jvp)
      isospring_model_force_jvp(m, x.data(), v.data(), v.data(), v.data(), out.data());
    else
      isospring_model_forces(m, x.data(), v.data(), out.data());
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  const int kinds[] = {ISOSPRING_TERM_SPRINGS, ISOSPRING_TERM_CELL_VOLUME,
                       ISOSPRING_TERM_CELL_SHEAR, ISOSPRING_TERM_POINT_VOLUME,
                       ISOSPRING_TERM_POINT_SHEAR};
  state.counters["particles"] = static_cast<double>(isospring_model_particle_count(m));
  state.counters["terms"] = static_cast<double>(isospring_model_term_count(m, kinds[kind]));
}

void BM_Springs(benchmark::State& s) {
  run(s, kSprings, 0, false);
}
void BM_SpringsJvp(benchmark::State& s) {
  run(s, kSprings, 0, true);
}
void BM_CellVolume(benchmark::State& s) {
  run(s, kCellVolume, 0, false);
}
void BM_CellVolumeJvp(benchmark::State& s) {
  run(s, kCellVolume, 0, true);
}
void BM_CellShear(benchmark::State& s) {
  run(s, kCellShear, 0, false);
}
void BM_CellShearJvp(benchmark::State& s) {
  run(s, kCellShear, 0, true);
}
void BM_PointVolume1(benchmark::State& s) {
  run(s, kPointVolume, 1, false);
}
void BM_PointVolume1Jvp(benchmark::State& s) {
  run(s, kPointVolume, 1, true);
}
void BM_PointShear1(benchmark::State& s) {
  run(s, kPointShear, 1, false);
}
void BM_PointShear1Jvp(benchmark::State& s) {
  run(s, kPointShear, 1, true);
}
void BM_PointVolume27(benchmark::State& s) {
  run(s, kPointVolume, 3, false);
}
void BM_PointVolume27Jvp(benchmark::State& s) {
  run(s, kPointVolume, 3, true);
}
void BM_PointShear27(benchmark::State& s) {
  run(s, kPointShear, 3, false);
}
void BM_PointShear27Jvp(benchmark::State& s) {
  run(s, kPointShear, 3, true);
}

// The 2D cells at 10^3, 10^4 and 10^5 particles (fitting/step_cost.hpp prices membranes' cells
// with the 10^4 rows).
void run_sheet(benchmark::State& state, int term, bool jvp) {
  const Handle m = sheet_cells(static_cast<int>(state.range(0)), term);
  const std::vector<double> x = state_of(m.get(), 0.01 * kSpacing, true),
                            v = state_of(m.get(), 0.1, false);
  std::vector<double> out(x.size());
  for (auto _ : state) {
    if (jvp)
      isospring_model_force_jvp(m.get(), x.data(), v.data(), v.data(), v.data(), out.data());
    else
      isospring_model_forces(m.get(), x.data(), v.data(), out.data());
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.counters["particles"] = static_cast<double>(isospring_model_particle_count(m.get()));
  state.counters["terms"] = static_cast<double>(isospring_model_term_count(m.get(), term));
}

void BM_CellArea2D(benchmark::State& s) {
  run_sheet(s, ISOSPRING_TERM_CELL_VOLUME, false);
}
void BM_CellArea2DJvp(benchmark::State& s) {
  run_sheet(s, ISOSPRING_TERM_CELL_VOLUME, true);
}
void BM_CellShear2D(benchmark::State& s) {
  run_sheet(s, ISOSPRING_TERM_CELL_SHEAR, false);
}
void BM_CellShear2DJvp(benchmark::State& s) {
  run_sheet(s, ISOSPRING_TERM_CELL_SHEAR, true);
}

#define SIZES(name) BENCHMARK(name)->Arg(10)->Arg(22)->Arg(46)->Unit(benchmark::kMicrosecond)
SIZES(BM_Springs);
SIZES(BM_SpringsJvp);
SIZES(BM_CellVolume);
SIZES(BM_CellVolumeJvp);
SIZES(BM_CellShear);
SIZES(BM_CellShearJvp);
SIZES(BM_PointVolume1);
SIZES(BM_PointVolume1Jvp);
SIZES(BM_PointShear1);
SIZES(BM_PointShear1Jvp);
#define SHEET_SIZES(name) \
  BENCHMARK(name)->Arg(32)->Arg(100)->Arg(316)->Unit(benchmark::kMicrosecond)
SHEET_SIZES(BM_CellArea2D);
SHEET_SIZES(BM_CellArea2DJvp);
SHEET_SIZES(BM_CellShear2D);
SHEET_SIZES(BM_CellShear2DJvp);
BENCHMARK(BM_PointVolume27)->Arg(10)->Arg(22)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PointVolume27Jvp)->Arg(10)->Arg(22)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PointShear27)->Arg(10)->Arg(22)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PointShear27Jvp)->Arg(10)->Arg(22)->Unit(benchmark::kMicrosecond);

// A reduced model with r basis vectors over n^3 particles (made-up numbers: the cost does not
// depend on them), then per step: the reduced step and the whole displacement field.
Handle reduced_model(int n, int r) {
  const Lattice l = lattice(n);
  const size_t rows = l.rest.size(), size = static_cast<size_t>(r);
  std::vector<double> eigenvalues(size), damping(size * size), step(size * size),
      basis(rows * size);
  for (size_t k = 0; k < size; ++k) eigenvalues[k] = 100.0 * static_cast<double>(k + 1);
  for (size_t k = 0; k < size * size; ++k) {
    damping[k] = 1e-3 * std::sin(0.3 * static_cast<double>(k));
    step[k] = 1e-3 * std::cos(0.7 * static_cast<double>(k));
  }
  for (size_t k = 0; k < basis.size(); ++k)
    basis[k] = 0.01 * std::sin(0.11 * static_cast<double>(k));
  char error[300];
  Handle m(isospring_model_create_reduced(3, l.masses.size(), l.rest.data(), nullptr, size, 1e-3,
                                          eigenvalues.data(), damping.data(), step.data(),
                                          basis.data(), error, sizeof(error)),
           isospring_model_free);
  check(m != nullptr, error);
  return m;
}

void BM_ReducedStepAndField(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0)), r = static_cast<int>(state.range(1));
  const Handle m = reduced_model(n, r);
  std::vector<double> g(static_cast<size_t>(r), 1e-3), q(g.size(), 0.0), qdot(g.size(), 0.0);
  std::vector<double> u(static_cast<size_t>(n) * n * n * 3);
  for (auto _ : state) {
    isospring_model_reduced_step(m.get(), g.data(), q.data(), qdot.data());
    isospring_model_expand(m.get(), q.data(), u.data());
    benchmark::DoNotOptimize(u.data());
    benchmark::ClobberMemory();
  }
  state.counters["particles"] = static_cast<double>(n * n * n);
}
BENCHMARK(BM_ReducedStepAndField)
    ->Args({10, 32})
    ->Args({22, 32})
    ->Args({46, 32})
    ->Args({10, 64})
    ->Args({22, 64})
    ->Args({46, 64})
    ->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
