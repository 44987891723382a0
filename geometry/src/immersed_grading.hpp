#pragma once
// Graded knots of an immersed background grid along one axis (immersed_cad.hpp, GradingPlane).
#include <vector>

#include "isospring/geometry/immersed_cad.hpp"

namespace isospring::geometry::detail {

/// The cell boundaries of [a, b] along `axis` (a first, b last, increasing): `base_cells` equal
/// cells when no plane grades this axis; otherwise the cells are placed by equidistributing the
/// density max over planes (r - 1) / ln(r) / min(H, smallest + (r - 1) |x - at|) (at least 1 / H),
/// H = (b - a) / base_cells: each cell holds an equal share (at most 1) of its integral. A share
/// of 1 near a plane is a cell as long as smallest + (r - 1) d at its near end d, i.e. the
/// progression smallest, smallest r, ...; where it reaches H, cells of H ln(r) / (r - 1) (so the
/// growth never exceeds r). Their number is the integral rounded up.
///
/// `breaks` (any order) are kept as cell boundaries: the interval is split there and each piece
/// gets its own cells by the same rule (so without grading planes a piece of length L holds
/// ceil(L / H) equal cells). Breaks within 1e-9 (b - a) of an end or of each other count once.
std::vector<double> graded_ticks(double a, double b, int base_cells,
                                 const std::vector<GradingPlane>& planes, int axis,
                                 const std::vector<double>& breaks = {});

}  // namespace isospring::geometry::detail
