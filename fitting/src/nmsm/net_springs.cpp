// Springs and cell terms of one control net through its particles (see net_springs.hpp).
#include "nmsm/net_springs.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "isospring/analysis/spring_volume.hpp"

namespace isospring::fitting::detail {

double bounding_box_diagonal(const std::vector<Eigen::Vector3d>& points) {
  if (points.empty()) return 0.0;
  Eigen::Vector3d lo = points.front(), hi = points.front();
  for (const auto& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return (hi - lo).norm();
}

void collect_block_pairs(const NetView& net, int reach,
                         const std::vector<Eigen::Vector3d>& positions, double tolerance,
                         std::set<std::pair<int, int>>& pairs, int& collapsed) {
  // Blocks of every size up to reach + 1: on a complete net the smaller blocks' pairs are among
  // the larger ones' (the set keeps each pair once); on an incomplete one they keep the cells
  // whose larger blocks reach a point without a particle.
  std::vector<int> corners;
  for (int r = 1; r <= reach; ++r) {
    int block[3], starts[3];
    for (int d = 0; d < 3; ++d) {
      block[d] = std::min(r + 1, net.n[static_cast<size_t>(d)]);
      starts[d] = net.n[static_cast<size_t>(d)] - block[d] + 1;
    }
    for (int k = 0; k < starts[2]; ++k)
      for (int j = 0; j < starts[1]; ++j)
        for (int i = 0; i < starts[0]; ++i) {
          corners.clear();
          for (int dk = 0; dk < block[2]; ++dk)
            for (int dj = 0; dj < block[1]; ++dj)
              for (int di = 0; di < block[0]; ++di)
                corners.push_back(net.particle(i + di, j + dj, k + dk));
          if (std::find(corners.begin(), corners.end(), -1) != corners.end()) continue;
          for (size_t a = 0; a < corners.size(); ++a)
            for (size_t b = a + 1; b < corners.size(); ++b) {
              const int s = std::min(corners[a], corners[b]), t = std::max(corners[a], corners[b]);
              if (s == t || (positions[s] - positions[t]).norm() <= tolerance) {
                // Counted once per block of the reach-1 size, as the single-size loop did.
                if (r == reach) ++collapsed;
                continue;
              }
              pairs.emplace(s, t);
            }
        }
  }
}

void add_springs(const std::set<std::pair<int, int>>& pairs, analysis::SpringNetwork& network) {
  for (const auto& [s, t] : pairs) {
    analysis::Spring spring;
    spring.i = s;
    spring.j = t;
    spring.rest_length = (network.positions[s] - network.positions[t]).norm();
    network.springs.push_back(spring);
  }
}

int add_net_cell_terms(const NetView& net, analysis::CellEnergy kind, double min_volume,
                       analysis::SpringNetwork& network) {
  const int dim = network.dimension;
  const int nk = dim == 3 ? net.n[2] : 2;
  int degenerate = 0;
  for (int k = 0; k + 1 < nk; ++k)
    for (int j = 0; j + 1 < net.n[1]; ++j)
      for (int i = 0; i + 1 < net.n[0]; ++i) {
        analysis::VolumeTerm term;
        term.kind = kind;
        bool complete = true;
        for (int a = 0; a < analysis::volume_corners(dim); ++a) {
          const int q =
              net.particle(i + (a & 1), j + ((a >> 1) & 1), dim == 3 ? k + ((a >> 2) & 1) : 0);
          complete = complete && q >= 0;
          term.particles[static_cast<size_t>(a)] = q;
        }
        if (!complete) continue;
        term.rest_volume = analysis::rest_cell_volume(network, term);
        if (!(std::abs(term.rest_volume) > min_volume)) {
          ++degenerate;
          continue;
        }
        network.volumes.push_back(term);
      }
  return degenerate;
}

std::string skipped_cells_warning(int count, analysis::CellEnergy kind) {
  if (count == 0) return "";
  return std::string("skipped the ") + (kind == analysis::CellEnergy::kShear ? "shear" : "volume") +
         " terms of " + std::to_string(count) + " net cells of zero volume (collapsed corners)";
}

}  // namespace isospring::fitting::detail
