#pragma once
// Which springs share a stiffness parameter [S15 4.13, Algorithm 5.1].
#include <vector>

#include "isospring/analysis/spring_network.hpp"

namespace isospring::fitting {

struct Grouping {
  std::vector<int> group_of_spring;  // spring -> group
  std::vector<double> centre;        // rest length that opened each group
  int num_groups() const { return static_cast<int>(centre.size()); }
};

/// Deterministic rest-length grouping: lengths are sorted; the smallest unassigned length L_a
/// opens a group that takes every spring with L0 <= L_a (1 + gamma) (so all of [L_a (1 - gamma),
/// L_a (1 + gamma)] that is still unassigned). gamma = 0 groups exactly equal lengths (to 1e-12
/// relative). Throws nurbs::InputError unless 0 <= gamma < 1.
Grouping group_by_rest_length(const analysis::SpringNetwork& network, double gamma);

/// One parameter per spring.
Grouping one_group_per_spring(const analysis::SpringNetwork& network);

}  // namespace isospring::fitting
