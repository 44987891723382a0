#pragma once
// The cost/accuracy trade-off of a set of models (e.g. one per model kind, with its cost per
// engine step and its worst held-out error): which are Pareto-optimal, and which is the most
// accurate within a budget. Both coordinates are minimised.
//
// A point is Pareto-optimal when no other point is at most as costly AND at most as wrong and
// strictly better in one of the two: the models a user should ever pick, whatever the budget.
// Equal points are all optimal (neither is better). A point with a non-finite coordinate (a
// model kind that failed) is never optimal and dominates none.
#include <vector>

namespace isospring::fitting {

struct CostError {
  double cost = 0.0;   // e.g. microseconds per engine step
  double error = 0.0;  // e.g. worst held-out %e_rms
};

/// Per point, whether it is Pareto-optimal (see above). O(n^2): n is a handful of model kinds.
std::vector<bool> pareto_optimal(const std::vector<CostError>& points);

/// Index of the point of lowest error among those with cost <= budget (on an error tie the
/// cheaper, then the first); -1 when none is within the budget. Non-finite points are skipped.
/// The chosen point is always Pareto-optimal.
int most_accurate_within(const std::vector<CostError>& points, double budget);

}  // namespace isospring::fitting
