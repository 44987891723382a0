// Graded knots of an immersed background grid (immersed_grading.hpp).
#include "immersed_grading.hpp"

#include <algorithm>
#include <cmath>

namespace isospring::geometry::detail {

std::vector<double> graded_ticks(double a, double b, int base_cells,
                                 const std::vector<GradingPlane>& planes, int axis) {
  const double length = b - a, base = length / base_cells;
  std::vector<GradingPlane> mine;
  for (const GradingPlane& p : planes)
    if (p.axis == axis && p.smallest < base) mine.push_back(p);
  std::vector<double> ticks;
  if (mine.empty()) {
    for (int i = 0; i <= base_cells; ++i) ticks.push_back(a + base * i);  // as before grading
    ticks.back() = b;
    return ticks;
  }
  // Cells per unit length. A cell that starts at distance d from a plane and holds one unit of
  // (r - 1) / ln(r) / (s + (r - 1) x) ends where s + (r - 1) x has grown by the factor r: its
  // length is s + (r - 1) d, so the cells form the progression s, s r, s r^2, ... Where that size
  // reaches the base length H the density stays at its value there, (r - 1) / ln(r) / H: cells of
  // H ln(r) / (r - 1) (0.81 H for r = 1.5), so the progression never jumps (for r -> 1 the
  // factor tends to 1).
  const auto density = [&](double x) {
    double rho = 1.0 / base;
    for (const GradingPlane& p : mine) {
      const double per_cell = p.ratio > 1.0 + 1e-12 ? (p.ratio - 1.0) / std::log(p.ratio) : 1.0;
      const double size = p.smallest + (p.ratio - 1.0) * std::abs(x - p.at);
      rho = std::max(rho, per_cell / std::min(size, base));
    }
    return rho;
  };
  // The density integrated by the midpoint rule on samples a hundred times finer than the
  // smallest cell: the knots need not be exact, only increasing and near the requested lengths.
  double smallest = base;
  for (const GradingPlane& p : mine) smallest = std::min(smallest, p.smallest);
  const long samples =
      std::max<long>(1000, static_cast<long>(std::ceil(100.0 * length / smallest)));
  const double dx = length / static_cast<double>(samples);
  std::vector<double> cumulative(static_cast<size_t>(samples) + 1, 0.0);
  for (long k = 0; k < samples; ++k)
    cumulative[static_cast<size_t>(k) + 1] =
        cumulative[static_cast<size_t>(k)] + dx * density(a + (static_cast<double>(k) + 0.5) * dx);
  const double total = cumulative.back();
  const int cells = std::max(1, static_cast<int>(std::ceil(total - 1e-9)));
  ticks.push_back(a);
  long k = 0;
  for (int i = 1; i < cells; ++i) {
    const double target = total * i / cells;
    while (cumulative[static_cast<size_t>(k) + 1] < target) ++k;
    const double lo = cumulative[static_cast<size_t>(k)],
                 hi = cumulative[static_cast<size_t>(k) + 1];
    ticks.push_back(a + (static_cast<double>(k) + (target - lo) / (hi - lo)) * dx);
  }
  ticks.push_back(b);
  return ticks;
}

}  // namespace isospring::geometry::detail
