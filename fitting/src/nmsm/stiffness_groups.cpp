// Rest-length grouping: a sweep over the sorted lengths.
#include "isospring/fitting/stiffness_groups.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "isospring/nurbs/error.hpp"

namespace isospring::fitting {

namespace {

// Sorted sweep: the smallest unassigned size opens a group that takes every size up to
// (1 + gamma) times it. Appends groups to `grouping.centre` and returns the group per item.
std::vector<int> group_sizes(const std::vector<double>& sizes, double gamma, Grouping& grouping) {
  std::vector<int> order(sizes.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return sizes[a] < sizes[b]; });
  std::vector<int> group(sizes.size(), -1);
  const double window = std::max(gamma, 1e-12);
  double limit = -1.0;
  const int first = grouping.num_groups();
  for (int s : order) {
    if (grouping.num_groups() == first || sizes[s] > limit) {
      grouping.centre.push_back(sizes[s]);
      limit = sizes[s] * (1.0 + window);
    }
    group[s] = grouping.num_groups() - 1;
  }
  return group;
}

}  // namespace

std::vector<bool> Grouping::volume_groups() const {
  std::vector<bool> result(centre.size(), false);
  for (int g : group_of_volume) result[static_cast<size_t>(g)] = true;
  return result;
}

Grouping group_by_rest_length(const analysis::SpringNetwork& network, double gamma) {
  if (!(gamma >= 0.0 && gamma < 1.0))
    throw nurbs::InputError("calibration gamma = " + std::to_string(gamma) +
                            " is outside [0, 1); [S15] uses values such as 0.5, 0.2, 0.01");
  Grouping grouping;
  std::vector<double> lengths;
  for (const auto& s : network.springs) lengths.push_back(s.rest_length);
  grouping.group_of_spring = group_sizes(lengths, gamma, grouping);
  // Cell terms by rest |volume|, each kind in groups of its own (a bulk modulus is not a shear
  // modulus, a net cell's mean strain is not a strain point's): cell volume terms first, then
  // cell shear terms, then the strain points' volume and shear terms.
  grouping.group_of_volume.assign(network.volumes.size(), -1);
  for (bool point : {false, true})
    for (auto kind : {analysis::CellEnergy::kVolume, analysis::CellEnergy::kShear}) {
      std::vector<double> volumes;
      std::vector<size_t> index;
      for (size_t v = 0; v < network.volumes.size(); ++v)
        if (network.volumes[v].kind == kind && network.volumes[v].points.empty() != point) {
          volumes.push_back(std::abs(network.volumes[v].rest_volume));
          index.push_back(v);
        }
      if (volumes.empty()) continue;
      const std::vector<int> group = group_sizes(volumes, gamma, grouping);
      for (size_t i = 0; i < index.size(); ++i) grouping.group_of_volume[index[i]] = group[i];
    }
  return grouping;
}

Grouping one_group_per_spring(const analysis::SpringNetwork& network) {
  Grouping grouping;
  for (size_t s = 0; s < network.springs.size(); ++s) {
    grouping.group_of_spring.push_back(static_cast<int>(s));
    grouping.centre.push_back(network.springs[s].rest_length);
  }
  for (size_t v = 0; v < network.volumes.size(); ++v) {
    grouping.group_of_volume.push_back(grouping.num_groups());
    grouping.centre.push_back(std::abs(network.volumes[v].rest_volume));
  }
  return grouping;
}

}  // namespace isospring::fitting
