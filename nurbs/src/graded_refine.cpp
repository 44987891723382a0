// Knot insertion graded towards the ends of a direction (graded_refine.hpp).
#include "isospring/nurbs/graded_refine.hpp"

#include <cmath>
#include <string>

#include "isospring/nurbs/error.hpp"
#include "isospring/nurbs/refine.hpp"

namespace isospring::nurbs {

namespace {

// s in [0, 1] -> t in [0, 1], graded as Grading describes.
double graded_map(double s, const Grading& g) {
  const double e = g.exponent;
  if (g.towards_start && g.towards_end)
    return s <= 0.5 ? 0.5 * std::pow(2.0 * s, e) : 1.0 - 0.5 * std::pow(2.0 * (1.0 - s), e);
  if (g.towards_start) return std::pow(s, e);
  if (g.towards_end) return 1.0 - std::pow(1.0 - s, e);
  return s;
}

}  // namespace

std::vector<double> graded_breakpoints(double a, double b, int n, const Grading& grading) {
  if (n < 1)
    throw InputError("graded refinement: the number of spans must be >= 1, got " +
                     std::to_string(n));
  if (!(grading.exponent >= 1.0) || !std::isfinite(grading.exponent))
    throw InputError("graded refinement: the grading exponent must be a finite number >= 1, got " +
                     std::to_string(grading.exponent));
  if (!(a < b))
    throw InputError("graded refinement: empty parameter range [" + std::to_string(a) + ", " +
                     std::to_string(b) + "]");
  std::vector<double> out(static_cast<size_t>(n) + 1);
  for (int i = 0; i <= n; ++i)
    out[static_cast<size_t>(i)] =
        a + (b - a) * graded_map(static_cast<double>(i) / static_cast<double>(n), grading);
  out.front() = a;  // exact ends whatever the rounding
  out.back() = b;
  return out;
}

Patch refine_graded(const Patch& patch, int dir, int elements, const Grading& grading) {
  if (dir < 0 || dir >= patch.param_dim())
    throw InputError("graded refinement: direction " + std::to_string(dir) +
                     " is not a direction of a " + std::to_string(patch.param_dim()) +
                     "-parametric patch");
  const KnotVector& kv = patch.knots(dir);
  const std::vector<double> breaks = graded_breakpoints(kv.first(), kv.last(), elements, grading);
  const std::vector<double> existing = kv.unique();
  const double tolerance = 1e-12 * (kv.last() - kv.first());
  std::vector<double> insert;
  for (size_t i = 1; i + 1 < breaks.size(); ++i) {
    bool present = false;
    for (double k : existing) present = present || std::abs(k - breaks[i]) <= tolerance;
    if (!present) insert.push_back(breaks[i]);
  }
  return refine_knots(patch, dir, insert);
}

}  // namespace isospring::nurbs
