// Memory estimates from sizes alone (resource_estimate.hpp).
#include "isospring/analysis/resource_estimate.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace isospring::analysis {

PatchSize refined_size(const nurbs::Patch& patch, const std::array<int, 3>& elevate,
                       const std::array<double, 3>& inserted, const std::array<double, 3>& splits) {
  PatchSize size;
  size.param_dim = patch.param_dim();
  for (int d = 0; d < patch.param_dim(); ++d) {
    const auto i = static_cast<size_t>(d);
    // Elevating by t raises the multiplicity of each distinct knot by t: t more points per span.
    double spans = patch.knots(d).num_elements();
    double points = patch.num_points(d) + elevate[i] * spans;
    points += inserted[i];  // one point per inserted knot
    spans += inserted[i];
    points += (splits[i] - 1.0) * spans;  // splits - 1 new single knots per span
    size.points[i] = points;
    size.degree[i] = patch.degree(d) + elevate[i];
  }
  return size;
}

SolveEstimate estimate_static_solve(const std::vector<PatchSize>& patches, int dofs_per_node) {
  SolveEstimate e;
  double full_nonzeros = 0;
  for (const PatchSize& p : patches) {
    double couplings = 1;  // basis functions overlapping one basis function (itself included)
    for (int d = 0; d < p.param_dim; ++d)
      couplings *=
          std::min(2.0 * p.degree[static_cast<size_t>(d)] + 1.0, p.points[static_cast<size_t>(d)]);
    const double dofs = dofs_per_node * p.total_points();
    e.dofs += dofs;
    full_nonzeros += dofs * dofs_per_node * couplings;
  }
  e.nonzeros = 0.5 * (full_nonzeros + e.dofs);
  constexpr double kBytesPerNonzero = 12.0;  // double value + int row index
  constexpr double kCopies = 3.0;            // K, reduced K, Cholesky factor (>= reduced K)
  e.bytes = kCopies * kBytesPerNonzero * e.nonzeros + geometry_bytes(patches);
  return e;
}

double geometry_bytes(const std::vector<PatchSize>& patches) {
  double points = 0;
  for (const PatchSize& p : patches) points += p.total_points();
  return 4.0 * sizeof(double) * points;
}

double available_memory_bytes() {
  std::ifstream meminfo("/proc/meminfo");
  std::string line;
  while (std::getline(meminfo, line)) {
    std::istringstream fields(line);
    std::string key;
    double kilobytes = 0;
    if (fields >> key >> kilobytes && key == "MemAvailable:") return kilobytes * 1024.0;
  }
  const long pages = ::sysconf(_SC_AVPHYS_PAGES), page_size = ::sysconf(_SC_PAGESIZE);
  return pages > 0 && page_size > 0 ? static_cast<double>(pages) * static_cast<double>(page_size)
                                    : 0.0;
}

std::string format_bytes(double bytes) {
  const char* units[] = {"B", "kB", "MB", "GB", "TB", "PB", "EB"};
  int unit = 0;
  while (bytes >= 1000.0 && unit < 6) {
    bytes /= 1000.0;
    ++unit;
  }
  char text[64];
  std::snprintf(text, sizeof(text), "%.3g %s", bytes, units[unit]);
  return text;
}

}  // namespace isospring::analysis
