#pragma once
// Knot insertion graded towards the ends of a parametric direction, for fields that are singular
// there (the stresses at the edges of a clamped face). Exact like every knot insertion: geometry
// and parametrisation do not change, so points keep their parameters.
//
// The grading is algebraic ("radical" meshes): with s = i / n uniform, the breakpoints of n spans
// towards the start are t = s^exponent. A field that behaves like t^a near the end is t^a =
// s^(a * exponent) in the uniform variable s, so the grading makes it smoother where the spans
// are uniform, and a family of such nets (n doubling at a fixed exponent) keeps a fixed error
// ratio per doubling, as uniform refinement does: the geometric convergence a Richardson estimate
// needs. Towards both ends the map is applied to each half (symmetric).
#include <vector>

#include "isospring/nurbs/patch.hpp"

namespace isospring::nurbs {

struct Grading {
  double exponent = 1.0;  // 1: uniform
  bool towards_start = false, towards_end = false;
  bool graded() const { return exponent != 1.0 && (towards_start || towards_end); }
};

/// The n + 1 breakpoints of n spans over [a, b] graded as described above (a and b included,
/// strictly increasing). Throws InputError for n < 1, exponent < 1 or a >= b.
std::vector<double> graded_breakpoints(double a, double b, int n, const Grading& grading);

/// `patch` refined along `dir` by inserting the interior breakpoints of graded_breakpoints over
/// the direction's whole range with n = `elements`; a breakpoint that is already a knot (within
/// 1e-12 of the range) is not inserted again, so a direction with interior knots ends with up to
/// elements + (its interior knots) spans.
Patch refine_graded(const Patch& patch, int dir, int elements, const Grading& grading);

}  // namespace isospring::nurbs
