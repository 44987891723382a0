#pragma once
// A random spring lattice for the analysis tests (force pass, reduced model).
#include <random>

#include "isospring/analysis/spring_mechanics.hpp"
#include "isospring/analysis/spring_network.hpp"

namespace isospring::analysis {

// n^dim lattice (edge and diagonal springs to the forward neighbours), positions jittered so no
// spring lies along an axis, random masses, stiffnesses and damping, face x = 0 fixed.
inline SpringNetwork random_lattice(int n, int dim, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.1, 0.1), factor(0.5, 2.0);
  SpringNetwork net;
  net.dimension = dim;
  const int nz = dim == 3 ? n : 1;
  auto index = [n](int i, int j, int k) { return (k * n + j) * n + i; };
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        net.positions.emplace_back(i + jitter(rng), j + jitter(rng),
                                   dim == 3 ? k + jitter(rng) : 0.0);
        net.masses.push_back(factor(rng));
        net.fixed.push_back(i == 0);
      }
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        for (int dk = 0; dk <= (dim == 3 ? 1 : 0); ++dk)
          for (int dj = -1; dj <= 1; ++dj)
            for (int di = -1; di <= 1; ++di) {
              const bool forward = dk > 0 || dj > 0 || (dj == 0 && di > 0);
              const int a = i + di, b = j + dj, c = k + dk;
              if (!forward || a < 0 || b < 0 || a >= n || b >= n || c >= nz) continue;
              Spring s;
              s.i = index(i, j, k);
              s.j = index(a, b, c);
              s.rest_length = (net.positions[s.i] - net.positions[s.j]).norm();
              s.stiffness = 1000.0 * factor(rng);
              net.springs.push_back(s);
            }
  assign_damping_ratio(net, 0.05);
  net.springs[3].damping = 0.0;  // the undamped branch too
  return net;
}

}  // namespace isospring::analysis
