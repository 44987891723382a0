#pragma once
// Transfinite (Coons) interpolation with NURBS, exactly: the bilinearly blended Coons patch of four
// boundary curves is itself a NURBS surface once the opposite curves share degree and knots.
//
// With Greville abscissae g_i (the B-spline coefficients of the linear function t), the control
// net of the Coons patch S = ruled_v(bottom, top) + ruled_u(left, right) - bilinear(corners) is
//   P_ij = (1-g_j) B_i + g_j T_i + (1-g_i) L_j + g_i R_j - bilinear(g_i, g_j),
// computed on homogeneous points (w x, w): the patch interpolates the four curves exactly,
// rational or not, once the curves' end weights agree at the corners (each curve may be scaled by
// a constant, which leaves it unchanged). For polynomial curves this is the classical (Euclidean)
// Coons patch. For rational curves it is the blend of the homogeneous curves: it interpolates the
// same boundary exactly but its interior differs from the Euclidean blend (whose denominator is a
// product of the curves' weight functions) unless the weights are compatible, e.g. rational
// curves in one direction with equal weights opposite straight lines (a cylinder between two
// arcs). The CAD import therefore accepts a Coons face only where it lies on the CAD surface.
#include <array>
#include <vector>

#include "isospring/nurbs/patch.hpp"

namespace isospring::geometry {

/// The same curves (param_dim 1) over [0, 1], raised to a common degree and refined to common
/// knots (exact: degree elevation and knot insertion). Knot values closer than `knot_tolerance`
/// (in [0, 1]) are taken as the same knot. Throws std::invalid_argument for non-curves.
std::vector<nurbs::Patch> make_compatible(const std::vector<nurbs::Patch>& curves,
                                          double knot_tolerance = 1e-10);

/// Coons patch over [0, 1]^2 with S(u, 0) = bottom(u), S(1, v) = right(v), S(u, 1) = top(u),
/// S(0, v) = left(v) (the curves are reparametrised to [0, 1] and made compatible in pairs).
/// Corners closer than `corner_tolerance` are merged (the curves' end control points move there);
/// farther apart, or rational curves whose end weights cannot be matched by scaling, throw
/// std::invalid_argument.
nurbs::Patch coons_patch(const nurbs::Patch& bottom, const nurbs::Patch& right,
                         const nurbs::Patch& top, const nurbs::Patch& left,
                         double corner_tolerance = 1e-9);

/// Trivariate transfinite (Coons) interpolation over [0, 1]^3 of six boundary faces, the Boolean
/// sum P_u + P_v + P_w - P_u P_v - P_v P_w - P_u P_w + P_u P_v P_w of the linear blends, exactly as
/// a NURBS volume (same Greville construction, homogeneous). Faces in the order u=0, u=1 (over
/// (v, w)), v=0, v=1 (over (u, w)), w=0, w=1 (over (u, v)), each over [0, 1]^2 with the same knot
/// vectors along shared directions. Shared edges and corners may differ by `tolerance` (they are
/// averaged); beyond that, or with different knots, throws std::invalid_argument. The volume's
/// boundary faces are the given faces.
nurbs::Patch coons_volume(const std::array<nurbs::Patch, 6>& faces, double tolerance = 1e-9);

/// Greville abscissae of a knot vector (averages of p consecutive interior knots).
std::vector<double> greville_abscissae(const nurbs::KnotVector& knots);

}  // namespace isospring::geometry
