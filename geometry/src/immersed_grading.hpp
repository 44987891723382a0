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
/// ceil(L / H) equal cells). Breaks closer than kSmallestCellFraction H (at least 1e-9 (b - a)) to
/// the previous one count once. A break that close to an end moves that end onto it when it lies
/// within `snap` of it (the part's tolerance: the box's end is the part's extreme face, known only
/// to that tolerance), else it is dropped. So no piece, and no ungraded cell, is thinner than
/// kSmallestCellFraction H; the first and last ticks are the (possibly moved) ends.
std::vector<double> graded_ticks(double a, double b, int base_cells,
                                 const std::vector<GradingPlane>& planes, int axis,
                                 const std::vector<double>& breaks = {}, double snap = 0.0);

/// Moves each end of [a, b] onto the nearest break within `snap` of it (inside or outside), if
/// any: a box end is the part's extreme face, known only to the B-rep's tolerance, while a
/// break is that face's exact plane.
void snap_ends(double& a, double& b, const std::vector<double>& breaks, double snap);

/// The thinnest cell a grid may have, as a fraction of its base cell length H. A cut cell's
/// octree and a face's pieces are sized by the thinnest cell they meet, so their number grows
/// like H over it; at 1e-3 a face 1e-7 m off a grid plane of a millimetre grid (a B-rep's
/// tolerance) no longer makes cells, while a break a thousandth of a cell off another changes
/// the volume by at most that fraction of the cell if dropped (it is then integrated as cut).
inline constexpr double kSmallestCellFraction = 1e-3;

}  // namespace isospring::geometry::detail
