// Rest-length grouping: a sweep over the sorted lengths.
#include "isospring/fitting/stiffness_groups.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "isospring/nurbs/error.hpp"

namespace isospring::fitting {

Grouping group_by_rest_length(const analysis::SpringNetwork& network, double gamma) {
  if (!(gamma >= 0.0 && gamma < 1.0))
    throw nurbs::InputError("calibration gamma = " + std::to_string(gamma) +
                            " is outside [0, 1); [S15] uses values such as 0.5, 0.2, 0.01");
  const auto& springs = network.springs;
  std::vector<int> order(springs.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return springs[a].rest_length < springs[b].rest_length; });
  Grouping grouping;
  grouping.group_of_spring.assign(springs.size(), -1);
  const double window = std::max(gamma, 1e-12);
  double limit = -1.0;
  for (int s : order) {
    const double length = springs[s].rest_length;
    if (grouping.centre.empty() || length > limit) {
      grouping.centre.push_back(length);
      limit = length * (1.0 + window);
    }
    grouping.group_of_spring[s] = grouping.num_groups() - 1;
  }
  return grouping;
}

Grouping one_group_per_spring(const analysis::SpringNetwork& network) {
  Grouping grouping;
  for (size_t s = 0; s < network.springs.size(); ++s) {
    grouping.group_of_spring.push_back(static_cast<int>(s));
    grouping.centre.push_back(network.springs[s].rest_length);
  }
  return grouping;
}

}  // namespace isospring::fitting
