#pragma once
// What one step of a spring model costs an engine: the engine runtime's force evaluation
// (runtime/include/isospring/runtime/runtime.h) per term, as bench/bench_runtime measured it on
// the project's 2-core machine (one thread, CPU time, 10^3-10^5 particles; README "Engine
// runtime"), summed over the model's terms. An estimate for choosing between model kinds by a
// budget (CalibrationSettings::max_step_us), not a measurement of the user's machine.
#include "isospring/analysis/spring_network.hpp"

namespace isospring::fitting {

/// Microseconds per force evaluation [us] of each term kind (per spring, per cell term, per
/// particle of a strain point), from bench_runtime's 10^4-particle rows.
struct StepCosts {
  double spring = 0.0058;          // 13 per particle: 735 us at 10^4 particles
  double cell_volume = 0.39;       // 3,615 us for 9,261 cells
  double cell_shear = 0.063;       // 587 us for 9,261 cells
  double point_particle = 0.0055;  // per particle of a strain point (volume or shear term)
  // The membranes' (2D) cells: bilinear area at 4 Gauss points, shear over 4 corners
  // (bench_runtime's n^2 sheets, 10^4 particles).
  double cell_area_2d = 0.043;   // 419 us for 9,801 cells
  double cell_shear_2d = 0.033;  // 322 us for 9,801 cells
};

/// Estimated microseconds of one force evaluation of `network` by the runtime.
double estimated_step_us(const analysis::SpringNetwork& network, const StepCosts& costs = {});

/// Throws nurbs::InputError when max_step_us > 0 and the network's estimate exceeds it, naming
/// both and the way out (cheaper model kinds); nothing otherwise.
void check_step_budget(const analysis::SpringNetwork& network, double max_step_us);

}  // namespace isospring::fitting
