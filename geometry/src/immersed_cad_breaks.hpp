#pragma once
// Break points where the topology of a cut cell's lines changes (immersed_cad_cells.cpp).
//
// A cut cell's rule splits its outer and middle intervals where the cell's edges and faces cross
// the boundary, and integrates each piece with Gauss rules of two orders whose difference decides
// whether the piece is bisected. Inside a piece, the number of crossings of the next level's lines
// changes where a section curve of the boundary has a tangent along the lines (a hole's extreme
// point) or a sharp edge crosses them. Such a change between the last Gauss abscissa of both orders
// and the piece's end is seen by neither order: their volumes agree while both miss the sliver
// (on a 6 x 6 x 6 grid over the CAx-IF L-bracket, a hole whose extreme lay 0.07 mm from a break
// cost 1.4e-4 of its cell). So each piece is sampled at its ends and at Gauss abscissae, and where
// the crossing count differs between neighbouring samples the change is located by bisection and
// becomes a break.
#include <functional>
#include <vector>

namespace isospring::geometry::detail {

/// `pieces` (sorted break points of an interval) refined at the changes of `signature` (the
/// topology of the lines at a coordinate): each piece is sampled `margin` inside its ends and at
/// the `samples` Gauss abscissae (on [-1, 1]); between two samples that differ the change is
/// located to `resolution` (a length) by bisection and added as a break unless it lies within
/// `margin` of a piece's end, and the new pieces are sampled in turn, at most `max_breaks` times
/// in all. `margin` is the distance within which a line parallel to a face is ambiguous (the
/// crossings' merge distance): a change found there is a face on the break itself, not a sliver.
/// `probes` are further coordinates sampled in whichever piece holds them (where the caller
/// knows the boundary passes: a change narrower than the Gauss abscissae' spacing is found there).
std::vector<double> topology_breaks(const std::vector<double>& pieces,
                                    const std::function<int(double)>& signature,
                                    const std::vector<double>& samples, double resolution,
                                    double margin, const std::vector<double>& probes = {},
                                    int max_breaks = 16);

}  // namespace isospring::geometry::detail
