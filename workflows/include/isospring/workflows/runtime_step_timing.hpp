#pragma once
// What one engine step of a calibrated model costs, MEASURED by running the engine runtime
// (runtime/include/isospring/runtime/runtime.h) on that model, beside fitting/step_cost.hpp's
// estimate (which sums per-term costs benchmarked on lattices).
//
// A network model goes through the same door an engine uses: io's model.json document, parsed by
// isospring_model_parse. A step is one isospring_model_forces and one isospring_model_force_jvp
// (what an implicit step's Krylov solver needs at least once) at a perturbed, moving state. A
// reduced model's step is isospring_model_reduced_step plus isospring_model_expand (the whole
// displacement field, what an engine renders each step). Time is the thread's CPU time (on a
// shared machine wall time counts the other users' processes); the median over `samples`
// samples, each of enough calls to last about a millisecond.
#include <string>

#include "isospring/analysis/spring_network.hpp"
#include "isospring/analysis/spring_reduced_model.hpp"

namespace isospring::workflows {

struct StepTimingOptions {
  int samples = 21;
  double sample_us = 1000.0;  // each sample repeats the step until it lasts this long
};

struct StepTiming {
  double median_us = 0.0;             // CPU microseconds per step
  double min_us = 0.0, max_us = 0.0;  // over the samples
  int samples = 0;
  long calls_per_sample = 0;
  /// Which runtime terms the model holds, as the runtime counted them after loading it.
  size_t springs = 0, cell_volume = 0, cell_shear = 0, point_volume = 0, point_shear = 0;
};

/// Measures a network's step. Throws std::runtime_error naming the runtime's message when the
/// runtime refuses the model (it should not: io wrote it).
StepTiming measure_network_step(const analysis::SpringNetwork& network,
                                const StepTimingOptions& options = {});

/// Measures a reduced model's step (built with isospring_model_create_reduced from the model's
/// basis, eigenvalues, damping and step matrix). Throws std::runtime_error when the runtime
/// refuses it.
StepTiming measure_reduced_step(const analysis::SpringNetwork& network,
                                const analysis::ReducedSpringModel& model,
                                const StepTimingOptions& options = {});

}  // namespace isospring::workflows
