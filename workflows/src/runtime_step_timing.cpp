// Measured engine step of a calibrated model through the runtime (runtime_step_timing.hpp).
#include "isospring/workflows/runtime_step_timing.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <ctime>
#include <memory>
#include <stdexcept>
#include <vector>

#include "isospring/io/model_file.hpp"
#include "isospring/runtime/runtime.h"

namespace isospring::workflows {

namespace {

using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

struct ModelDeleter {
  void operator()(isospring_model* m) const { isospring_model_free(m); }
};
using ModelPtr = std::unique_ptr<isospring_model, ModelDeleter>;

double thread_cpu_us() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return 1e6 * static_cast<double>(t.tv_sec) + 1e-3 * static_cast<double>(t.tv_nsec);
}

// Runs `step` in samples of enough calls to last options.sample_us (doubling from 1, after one
// warm-up call) and returns the per-call statistics.
template <class Step>
StepTiming time_steps(Step&& step, const StepTimingOptions& options) {
  step();
  long calls = 1;
  for (;;) {
    const double start = thread_cpu_us();
    for (long c = 0; c < calls; ++c) step();
    if (thread_cpu_us() - start >= options.sample_us || calls >= (1L << 24)) break;
    calls *= 2;
  }
  std::vector<double> per_call;
  for (int s = 0; s < std::max(1, options.samples); ++s) {
    const double start = thread_cpu_us();
    for (long c = 0; c < calls; ++c) step();
    per_call.push_back((thread_cpu_us() - start) / static_cast<double>(calls));
  }
  std::sort(per_call.begin(), per_call.end());
  StepTiming t;
  t.samples = static_cast<int>(per_call.size());
  t.calls_per_sample = calls;
  t.median_us = per_call[per_call.size() / 2];
  t.min_us = per_call.front();
  t.max_us = per_call.back();
  return t;
}

// A deterministic smooth pattern of the given amplitude on `n` numbers: a perturbed, moving
// state exercises every branch a real step takes (no zero-length or zero-velocity shortcut).
std::vector<double> pattern(size_t n, double amplitude, double phase) {
  std::vector<double> v(n);
  for (size_t i = 0; i < n; ++i) v[i] = amplitude * std::sin(1.3 * static_cast<double>(i) + phase);
  return v;
}

}  // namespace

StepTiming measure_network_step(const analysis::SpringNetwork& network,
                                const StepTimingOptions& options) {
  const std::string text = io::model_to_json(network).dump();
  char error[512];
  ModelPtr model(
      isospring_model_parse(text.data(), text.size(), "calibrated model", error, sizeof error));
  if (!model) throw std::runtime_error(std::string("runtime step timing: ") + error);
  const size_t n = isospring_model_state_size(model.get());
  // Amplitude 1e-3 of the model's extent: a small deformation, as the calibration's.
  Eigen::AlignedBox3d box;
  for (const auto& p : network.positions) box.extend(p);
  const double size = box.isEmpty() ? 1.0 : std::max(box.diagonal().norm(), 1e-12);
  std::vector<double> x(isospring_model_rest_positions(model.get()),
                        isospring_model_rest_positions(model.get()) + n);
  const std::vector<double> du = pattern(n, 1e-3 * size, 0.3);
  for (size_t i = 0; i < n; ++i) x[i] += du[i];
  const std::vector<double> v = pattern(n, 1e-2 * size, 1.1), dx = pattern(n, 1e-3 * size, 2.0);
  std::vector<double> f(n), df(n);
  const StepTiming measured = time_steps(
      [&] {
        isospring_model_forces(model.get(), x.data(), v.data(), f.data());
        isospring_model_force_jvp(model.get(), x.data(), v.data(), dx.data(), nullptr, df.data());
      },
      options);
  StepTiming t = measured;
  t.springs = isospring_model_term_count(model.get(), ISOSPRING_TERM_SPRINGS);
  t.cell_volume = isospring_model_term_count(model.get(), ISOSPRING_TERM_CELL_VOLUME);
  t.cell_shear = isospring_model_term_count(model.get(), ISOSPRING_TERM_CELL_SHEAR);
  t.point_volume = isospring_model_term_count(model.get(), ISOSPRING_TERM_POINT_VOLUME);
  t.point_shear = isospring_model_term_count(model.get(), ISOSPRING_TERM_POINT_SHEAR);
  return t;
}

StepTiming measure_reduced_step(const analysis::SpringNetwork& network,
                                const analysis::ReducedSpringModel& reduced,
                                const StepTimingOptions& options) {
  const int dim = network.dimension;
  const size_t particles = network.positions.size();
  std::vector<double> rest;
  std::vector<unsigned char> fixed;
  for (size_t q = 0; q < particles; ++q) {
    for (int c = 0; c < dim; ++c) rest.push_back(network.positions[q][c]);
    fixed.push_back(network.fixed[q] ? 1 : 0);
  }
  const size_t r = static_cast<size_t>(reduced.size());
  const RowMajor damping = reduced.damping(), step = reduced.step_inverse(),
                 basis = reduced.basis();
  const Eigen::VectorXd lambda = reduced.eigenvalues();
  char error[512];
  ModelPtr model(isospring_model_create_reduced(dim, particles, rest.data(), fixed.data(), r,
                                                reduced.dt(), lambda.data(), damping.data(),
                                                step.data(), basis.data(), error, sizeof error));
  if (!model) throw std::runtime_error(std::string("runtime step timing: ") + error);
  std::vector<double> g = pattern(r, 1e-3, 0.5), q(r, 0.0), qdot(r, 0.0);
  std::vector<double> u(particles * static_cast<size_t>(dim));
  return time_steps(
      [&] {
        isospring_model_reduced_step(model.get(), g.data(), q.data(), qdot.data());
        isospring_model_expand(model.get(), q.data(), u.data());
      },
      options);
}

}  // namespace isospring::workflows
