#pragma once
// Which springs share a stiffness parameter [S15 4.13, Algorithm 5.1].
#include <vector>

#include "isospring/analysis/spring_network.hpp"

namespace isospring::fitting {

struct Grouping {
  std::vector<int> group_of_spring;  // spring -> group
  /// Volume term (SpringNetwork::volumes) -> group; its groups follow the spring groups and never
  /// share a parameter with springs (a modulus [Pa] is not a stiffness [N/m]). Empty when the
  /// network has no volume terms.
  std::vector<int> group_of_volume;
  std::vector<double> centre;  // rest length (volume groups: rest |volume|) that opened each group
  int num_groups() const { return static_cast<int>(centre.size()); }
  /// Per group: true when it holds volume terms.
  std::vector<bool> volume_groups() const;
};

/// Deterministic rest-length grouping: lengths are sorted; the smallest unassigned length L_a
/// opens a group that takes every spring with L0 <= L_a (1 + gamma) (so all of [L_a (1 - gamma),
/// L_a (1 + gamma)] that is still unassigned). gamma = 0 groups exactly equal lengths (to 1e-12
/// relative). Throws nurbs::InputError unless 0 <= gamma < 1.
Grouping group_by_rest_length(const analysis::SpringNetwork& network, double gamma);

/// Volume terms are grouped the same way by their rest |volume|, in groups after the springs';
/// shear terms (analysis::CellEnergy::kShear) likewise, in groups after the volume terms'.

/// One parameter per spring (and per volume term).
Grouping one_group_per_spring(const analysis::SpringNetwork& network);

}  // namespace isospring::fitting
