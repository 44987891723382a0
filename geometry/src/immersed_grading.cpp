// Graded knots of an immersed background grid (immersed_grading.hpp).
#include "immersed_grading.hpp"

#include <algorithm>
#include <cmath>

namespace isospring::geometry::detail {

namespace {

// Cells per unit length. A cell that starts at distance d from a plane and holds one unit of
// (r - 1) / ln(r) / (s + (r - 1) x) ends where s + (r - 1) x has grown by the factor r: its
// length is s + (r - 1) d, so the cells form the progression s, s r, s r^2, ... Where that size
// reaches the base length H the density stays at its value there, (r - 1) / ln(r) / H: cells of
// H ln(r) / (r - 1) (0.81 H for r = 1.5), so the progression never jumps (for r -> 1 the
// factor tends to 1).
double density(double x, double base, const std::vector<GradingPlane>& planes) {
  double rho = 1.0 / base;
  for (const GradingPlane& p : planes) {
    const double per_cell = p.ratio > 1.0 + 1e-12 ? (p.ratio - 1.0) / std::log(p.ratio) : 1.0;
    const double size = p.smallest + (p.ratio - 1.0) * std::abs(x - p.at);
    rho = std::max(rho, per_cell / std::min(size, base));
  }
  return rho;
}

// The cells of [lo, hi] (appended to `ticks` after lo, hi last) by equidistributing the density,
// integrated by the midpoint rule on samples a hundred times finer than the smallest cell: the
// knots need not be exact, only increasing and near the requested lengths.
void equidistribute(double lo, double hi, double base, const std::vector<GradingPlane>& planes,
                    std::vector<double>& ticks) {
  const double length = hi - lo;
  if (planes.empty()) {  // equal cells, exactly
    const int cells = std::max(1, static_cast<int>(std::ceil(length / base - 1e-9)));
    for (int i = 1; i < cells; ++i) ticks.push_back(lo + length * i / cells);
    ticks.push_back(hi);
    return;
  }
  double smallest = base;
  for (const GradingPlane& p : planes) smallest = std::min(smallest, p.smallest);
  const long samples =
      std::max<long>(1000, static_cast<long>(std::ceil(100.0 * length / smallest)));
  const double dx = length / static_cast<double>(samples);
  std::vector<double> cumulative(static_cast<size_t>(samples) + 1, 0.0);
  for (long k = 0; k < samples; ++k)
    cumulative[static_cast<size_t>(k) + 1] =
        cumulative[static_cast<size_t>(k)] +
        dx * density(lo + (static_cast<double>(k) + 0.5) * dx, base, planes);
  const double total = cumulative.back();
  const int cells = std::max(1, static_cast<int>(std::ceil(total - 1e-9)));
  long k = 0;
  for (int i = 1; i < cells; ++i) {
    const double target = total * i / cells;
    while (cumulative[static_cast<size_t>(k) + 1] < target) ++k;
    const double c0 = cumulative[static_cast<size_t>(k)],
                 c1 = cumulative[static_cast<size_t>(k) + 1];
    ticks.push_back(lo + (static_cast<double>(k) + (target - c0) / (c1 - c0)) * dx);
  }
  ticks.push_back(hi);
}

}  // namespace

void snap_ends(double& a, double& b, const std::vector<double>& breaks, double snap) {
  double to_a = snap, to_b = snap;  // the nearest break within `snap` wins
  double new_a = a, new_b = b;
  for (double x : breaks) {
    if (std::abs(x - a) <= to_a) to_a = std::abs(x - a), new_a = x;
    if (std::abs(x - b) <= to_b) to_b = std::abs(x - b), new_b = x;
  }
  if (new_b - new_a > 0.5 * (b - a)) a = new_a, b = new_b;
}

std::vector<double> graded_ticks(double a, double b, int base_cells,
                                 const std::vector<GradingPlane>& planes, int axis,
                                 const std::vector<double>& breaks, double snap) {
  const double length = b - a, base = length / base_cells;
  std::vector<GradingPlane> mine;
  for (const GradingPlane& p : planes)
    if (p.axis == axis && p.smallest < base) mine.push_back(p);
  // The pieces' ends: a, the breaks strictly inside, b. A break closer than `close` to an end or
  // to the previous break would make a cell that thin (a sliver, whose cut-cell and face pieces
  // follow its width): at an end within `snap` (the part's own tolerance) the end moves onto it,
  // so the face stays on a grid plane; otherwise the break is dropped and the face cuts a cell of
  // normal size.
  const double close = std::max(kSmallestCellFraction * base, 1e-9 * length);
  std::vector<double> inner(breaks);
  std::sort(inner.begin(), inner.end());
  snap_ends(a, b, inner, std::min(snap, close));
  std::vector<double> ends{a};
  for (double x : inner)
    if (x > ends.back() + close && x < b - close) ends.push_back(x);
  ends.push_back(b);
  std::vector<double> ticks{a};
  if (mine.empty() && ends.size() == 2) {
    const double h = (b - a) / base_cells;
    for (int i = 1; i <= base_cells; ++i) ticks.push_back(a + h * i);  // as before grading
    ticks.back() = b;
    return ticks;
  }
  for (size_t i = 1; i < ends.size(); ++i) equidistribute(ends[i - 1], ends[i], base, mine, ticks);
  return ticks;
}

}  // namespace isospring::geometry::detail
