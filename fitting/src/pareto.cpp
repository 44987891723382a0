// Pareto set and budgeted choice of cost/error points (pareto.hpp).
#include "isospring/fitting/pareto.hpp"

#include <cmath>

namespace isospring::fitting {

namespace {

bool finite(const CostError& p) {
  return std::isfinite(p.cost) && std::isfinite(p.error);
}

// a dominates b: no worse in both, strictly better in one.
bool dominates(const CostError& a, const CostError& b) {
  return a.cost <= b.cost && a.error <= b.error && (a.cost < b.cost || a.error < b.error);
}

}  // namespace

std::vector<bool> pareto_optimal(const std::vector<CostError>& points) {
  std::vector<bool> optimal(points.size(), false);
  for (size_t i = 0; i < points.size(); ++i) {
    if (!finite(points[i])) continue;
    bool dominated = false;
    for (size_t j = 0; j < points.size() && !dominated; ++j)
      dominated = j != i && finite(points[j]) && dominates(points[j], points[i]);
    optimal[i] = !dominated;
  }
  return optimal;
}

int most_accurate_within(const std::vector<CostError>& points, double budget) {
  int best = -1;
  for (size_t i = 0; i < points.size(); ++i) {
    const CostError& p = points[i];
    if (!finite(p) || p.cost > budget) continue;
    if (best < 0 || p.error < points[best].error ||
        (p.error == points[best].error && p.cost < points[best].cost))
      best = static_cast<int>(i);
  }
  return best;
}

}  // namespace isospring::fitting
