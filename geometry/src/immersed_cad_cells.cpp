// Cut-cell quadrature along exact lines (immersed_cad_cells.hpp).
#include "immersed_cad_cells.hpp"

#include "immersed_cad_breaks.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "isospring/nurbs/quadrature.hpp"

namespace isospring::geometry::detail {

namespace {

// [lo, hi] cut at the break points inside it.
std::vector<double> pieces(double lo, double hi, std::vector<double> breaks) {
  breaks.push_back(lo);
  breaks.push_back(hi);
  std::sort(breaks.begin(), breaks.end());
  std::vector<double> kept;
  for (double b : breaks) {
    if (b < lo || b > hi) continue;
    if (!kept.empty() && b - kept.back() <= 1e-13 * (hi - lo)) continue;
    kept.push_back(b);
  }
  kept.back() = hi;
  return kept;
}

// The axis closest to the boundary's normals in the box: along it, the boundary is a graph over
// the cross section and the lines cross it at a clear angle.
int line_axis(const std::vector<const BoundaryPoint*>& boundary) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const BoundaryPoint* b : boundary) sum += b->weight * b->normal.cwiseAbs();
  if (sum.isZero()) return 2;
  int axis = 0;
  sum.maxCoeff(&axis);
  return axis;
}

// Within this distance of a box's face, a break, a piece or the end of a line's inside interval
// is the part's face lying on the box's face (a grid plane kept through ImmersionOptions::breaks,
// or met by chance), not the boundary crossing the box. OpenCascade resolves a point on a face
// only to its confusion (Precision::Confusion(), 1e-7 model units): on an L block with its faces
// on grid planes, the lines along those faces ended about 1e-11 m short of them, topology breaks
// fell 1e-8 m in, and lines in the pieces that thin beside a face (which run within the confusion
// of the face's plane) came back empty or with breaks 1e-5 m in. Counted as crossings, these
// made every cell along such a face cut. A part's face that far inside a box is lost from its
// volume by at most 1e-7 x the face's area.
constexpr double kOnBoxFace = 1e-7;

// How closely a change of topology is located: to 1e-10 of the box, but no closer than a tenth
// of OpenCascade's confusion (below it the lines' answers are noise, and each halving costs a
// line or four).
double resolution(double lo, double hi) {
  return std::max(1e-10 * (hi - lo), std::min(0.1 * kOnBoxFace, 1e-6 * (hi - lo)));
}

// Lines on the box's faces are moved inside by a hair, so that a face of the part lying in the
// box's face plane is met on one side, not along the line.
Eigen::Vector3d hair(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  return 1e-9 * (hi - lo);
}

// The cross section's sides, whose topology is sampled, lie this far inside the box's faces: 1e-6
// (or a thousandth of a small box), ten times OpenCascade's confusion. A hair in (hair()), on a
// part whose faces lie on the grid's planes, they ran along those faces, where the holed plate's
// rims are tori tangent to them: such a line grazes a torus, its answer flickered from one outer
// coordinate to the next, and each flicker became a break (up to 16 per box, each piece with its
// own abscissae and lines: five times the lines). A curved face reaching less than this into the
// box through a side changes the cross section there by a sliver of that depth, which is left to
// the Gauss-order estimate.
Eigen::Vector3d side_inset(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  Eigen::Vector3d s;
  for (int k = 0; k < 3; ++k)
    s[k] = std::max(1e-9 * (hi[k] - lo[k]), std::min(1e-6, 1e-3 * (hi[k] - lo[k])));
  return s;
}

// How a line's inside intervals meet [lo, hi]: whether it starts inside and how many of their
// ends lie strictly within (capped, as a small code).
int line_signature(const std::vector<Interval>& inside, double lo, double hi) {
  int ends = 0;
  for (const Interval& piece : inside) ends += (piece.lo > lo) + (piece.hi < hi);
  const bool starts_inside = !inside.empty() && inside.front().lo <= lo;
  return 2 * std::min(ends, 3) + (starts_inside ? 1 : 0);
}

// Outer coordinates where the cross section's sides may change topology between the Gauss
// abscissae: a side sweeps one of the box's four faces along a, and changes where the boundary's
// curve in that face turns back along a. A curve running across the face (a cylinder poking
// through the face, its extreme a sliver beyond it: on a 7^3 grid over the CAx-IF bolt the
// head's rim left 1e-4 of a cell, 0.35 mm wide of 2.1, between the abscissae) is met by lines
// along a across the face: their crossings and the midpoints between them are sampled.
std::vector<double> face_probes(SolidProbe& probe, const Eigen::Vector3d& lo,
                                const Eigen::Vector3d& hi, int d) {
  const int a = (d + 1) % 3, b = (d + 2) % 3;
  const Eigen::Vector3d e = hair(lo, hi);
  std::vector<double> hits;
  for (const int normal : {b, d}) {
    const int across = normal == b ? d : b;
    for (double side : {lo[normal] + e[normal], hi[normal] - e[normal]})
      for (double f : {1.0 / 6.0, 0.5, 5.0 / 6.0}) {
        Eigen::Vector3d p = lo;
        p[normal] = side;
        p[across] = lo[across] + f * (hi[across] - lo[across]);
        for (double t : probe.crossings(p, a, lo[a], hi[a])) hits.push_back(t);
      }
  }
  std::sort(hits.begin(), hits.end());
  std::vector<double> probes = hits;
  for (size_t k = 0; k + 1 < hits.size(); ++k) probes.push_back(0.5 * (hits[k] + hits[k + 1]));
  return probes;
}

// The outer interval [lo[a], hi[a]] cut where the box's four edges along a (a = d + 1) cross the
// boundary, where the solid's edges enter, leave or turn in the cross section, and where the
// topology of the cross section changes (sampled at `samples`, Gauss abscissae on [-1, 1]): the
// same for every Gauss order, so found once per box.
std::vector<double> outer_pieces(SolidProbe& probe, const Eigen::Vector3d& lo,
                                 const Eigen::Vector3d& hi, int d,
                                 const std::vector<double>& samples) {
  const int a = (d + 1) % 3, b = (d + 2) % 3;
  const Eigen::Vector3d e = hair(lo, hi);
  std::vector<double> breaks;
  for (double sb : {lo[b] + e[b], hi[b] - e[b]})
    for (double sd : {lo[d] + e[d], hi[d] - e[d]}) {
      Eigen::Vector3d p = lo;
      p[b] = sb;
      p[d] = sd;
      for (double t : probe.crossings(p, a, lo[a], hi[a])) breaks.push_back(t);
    }
  // Where the solid's edges enter or leave the cross section, end or turn back along a
  // (immersed_cad_edges.hpp).
  for (const int normal : {b, d})
    for (double at : {lo[normal] + e[normal], hi[normal] - e[normal]})
      for (double t : probe.edges().crossings(lo, hi, normal, at, a)) breaks.push_back(t);
  for (double t : probe.edges().turning_points(lo, hi, a)) breaks.push_back(t);
  // The topology of the box's cross section at outer coordinate t (see immersed_cad_breaks.hpp):
  // how its four sides (the lines along b at d = lo, hi and along d at b = lo, hi) meet the part.
  // It changes where a section curve of the boundary has a tangent along the cross section (a
  // hole's extreme point) or a face normal to a crosses it without reaching the box's edges (a
  // face a sliver away from the box's face).
  const Eigen::Vector3d s = side_inset(lo, hi);
  const auto section = [&](double t) {
    int n = 0;
    for (int side = 0; side < 4; ++side) {
      const int along = side < 2 ? b : d, across = side < 2 ? d : b;
      Eigen::Vector3d p = lo;
      p[a] = t;
      p[across] = side % 2 == 0 ? lo[across] + s[across] : hi[across] - s[across];
      n = 8 * n +
          line_signature(probe.inside(p, along, lo[along], hi[along]), lo[along], hi[along]);
    }
    return n;
  };
  return topology_breaks(pieces(lo[a], hi[a], breaks), section, samples, resolution(lo[a], hi[a]),
                         2.0 * probe.merge_distance(), face_probes(probe, lo, hi, d));
}

// The lines along d of one outer abscissa, kept by their middle coordinate: the middle pieces'
// topology check and the rule ask for the same lines at the Gauss abscissae.
class DLines {
 public:
  DLines(SolidProbe& probe, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int d, double xa)
      : probe_(probe), lo_(lo), hi_(hi), d_(d), xa_(xa) {}
  const std::vector<Interval>& at(double xb) {
    for (const auto& [t, line] : lines_)
      if (t == xb) return line;
    const int a = (d_ + 1) % 3, b = (d_ + 2) % 3;
    Eigen::Vector3d p = lo_;
    p[a] = xa_;
    p[b] = xb;
    lines_.emplace_back(xb, probe_.inside(p, d_, lo_[d_], hi_[d_]));
    return lines_.back().second;
  }

 private:
  SolidProbe& probe_;
  const Eigen::Vector3d &lo_, &hi_;
  int d_;
  double xa_;
  std::vector<std::pair<double, std::vector<Interval>>> lines_;
};

// The Gauss abscissa k of `g` on [x0, x1] and its weight (the same expression as the topology
// check's samples, so that DLines finds the lines it asked for).
double abscissa(const nurbs::GaussRule& g, size_t k, double x0, double x1) {
  return 0.5 * (x0 + x1) + 0.5 * (x1 - x0) * g.points[k];
}

// The middle interval at outer abscissa xa, cut where the lines along b in the box's two faces
// normal to d cross the boundary, where the solid's edges cross the section, and where the lines
// along d change their topology (a face normal to b that reaches neither of those faces, a
// silhouette of the boundary along d).
std::vector<double> middle_pieces(SolidProbe& probe, const Eigen::Vector3d& lo,
                                  const Eigen::Vector3d& hi, int d, double xa,
                                  const nurbs::GaussRule& g, DLines& lines) {
  const int a = (d + 1) % 3, b = (d + 2) % 3;
  const Eigen::Vector3d e = hair(lo, hi);
  std::vector<double> breaks;
  for (double sd : {lo[d] + e[d], hi[d] - e[d]}) {
    Eigen::Vector3d p = lo;
    p[a] = xa;
    p[d] = sd;
    for (double t : probe.crossings(p, b, lo[b], hi[b])) breaks.push_back(t);
  }
  for (double t : probe.edges().crossings(lo, hi, a, xa, b)) breaks.push_back(t);
  const auto topology = [&](double t) { return line_signature(lines.at(t), lo[d], hi[d]); };
  return topology_breaks(pieces(lo[b], hi[b], breaks), topology, g.points, resolution(lo[b], hi[b]),
                         2.0 * probe.merge_distance());
}

// Does a break in (lo, hi) lie farther than kOnBoxFace from both ends?
bool breaks_inside(const std::vector<double>& breaks) {
  const double lo = breaks.front() + kOnBoxFace, hi = breaks.back() - kOnBoxFace;
  for (size_t k = 1; k + 1 < breaks.size(); ++k)
    if (breaks[k] > lo && breaks[k] < hi) return true;
  return false;
}

// Does the piece [p0, p1] of [lo, hi] lie within kOnBoxFace of one of its ends? Its lines run
// along the box's face, where OpenCascade's answer for a face on that plane is ambiguous.
bool on_box_face(double p0, double p1, double lo, double hi) {
  return p1 <= lo + kOnBoxFace || p0 >= hi - kOnBoxFace;
}

// Whether the boundary crosses a box: some line ends or some break lies inside it (beyond
// kOnBoxFace of its faces), or some lines are wholly inside and others wholly outside the part.
struct CrossingTally {
  bool crossed = false;
  int full = 0, empty = 0;
  void line(const std::vector<Interval>& inside, double lo, double hi) {
    if (inside.empty())
      ++empty;
    else if (inside.size() == 1 && inside[0].lo <= lo + kOnBoxFace &&
             inside[0].hi >= hi - kOnBoxFace)
      ++full;
    else
      crossed = true;
  }
  // A box all of whose lines lie in pieces beside its faces (thinner than 2 x kOnBoxFace) is
  // crossed: nothing else decides it.
  bool result() const { return crossed || (full > 0) == (empty > 0); }
};

// Dimension by dimension: outer axis a, middle axis b, lines along d (see immersed_cad.hpp).
CutCellRule line_rule(SolidProbe& probe, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                      int d, const std::vector<double>& outer, int order) {
  const int a = (d + 1) % 3, b = (d + 2) % 3;
  CutCellRule rule;
  const nurbs::GaussRule& g = nurbs::gauss_legendre_cached(order);
  CrossingTally tally;
  tally.crossed = breaks_inside(outer);
  for (size_t i = 0; i + 1 < outer.size(); ++i) {
    const bool outer_on_face = on_box_face(outer[i], outer[i + 1], lo[a], hi[a]);
    for (size_t ga = 0; ga < g.points.size(); ++ga) {
      const double xa = abscissa(g, ga, outer[i], outer[i + 1]);
      const double wa = 0.5 * (outer[i + 1] - outer[i]) * g.weights[ga];
      DLines lines(probe, lo, hi, d, xa);
      const std::vector<double> middle = middle_pieces(probe, lo, hi, d, xa, g, lines);
      if (!outer_on_face && breaks_inside(middle)) tally.crossed = true;
      for (size_t j = 0; j + 1 < middle.size(); ++j) {
        const bool on_face = outer_on_face || on_box_face(middle[j], middle[j + 1], lo[b], hi[b]);
        for (size_t gb = 0; gb < g.points.size(); ++gb) {
          const double xb = abscissa(g, gb, middle[j], middle[j + 1]);
          const double wb = 0.5 * (middle[j + 1] - middle[j]) * g.weights[gb];
          const std::vector<Interval>& inside = lines.at(xb);
          if (!on_face) tally.line(inside, lo[d], hi[d]);
          Eigen::Vector3d p = lo;
          p[a] = xa;
          p[b] = xb;
          for (const Interval& piece : inside)
            for (size_t gd = 0; gd < g.points.size(); ++gd) {
              const double hd = 0.5 * (piece.hi - piece.lo);
              p[d] = piece.lo + hd * (1.0 + g.points[gd]);
              rule.points.push_back(p);
              rule.weights.push_back(wa * wb * hd * g.weights[gd]);
            }
        }
      }
    }
  }
  rule.crossed = tally.result();
  rule.inside = !rule.crossed && tally.full > 0;
  return rule;
}

double sum(const std::vector<double>& w) {
  double s = 0.0;
  for (double x : w) s += x;
  return s;
}

}  // namespace

CutCellRule cut_cell_rule(SolidProbe& probe, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                          const std::vector<const BoundaryPoint*>& boundary,
                          const CutCellSettings& settings, double cell_volume, CutCellStats& stats,
                          int depth) {
  ++stats.boxes;
  const int d = line_axis(boundary);
  const std::vector<double> outer =
      outer_pieces(probe, lo, hi, d, nurbs::gauss_legendre_cached(settings.order + 2).points);
  CutCellRule low = line_rule(probe, lo, hi, d, outer, settings.order);
  CutCellRule high = line_rule(probe, lo, hi, d, outer, settings.order + 2);
  const double error = std::abs(sum(low.weights) - sum(high.weights));
  if (error <= settings.tolerance * cell_volume) return low;
  if (depth >= settings.max_depth) {
    ++stats.unresolved;
    stats.unresolved_error += error;
    return high;
  }
  // Eight children, each with the boundary points inside it.
  CutCellRule rule;
  rule.crossed = true;
  const Eigen::Vector3d mid = 0.5 * (lo + hi);
  for (int c = 0; c < 8; ++c) {
    Eigen::Vector3d clo, chi;
    for (int k = 0; k < 3; ++k) {
      const bool upper = (c >> k) & 1;
      clo[k] = upper ? mid[k] : lo[k];
      chi[k] = upper ? hi[k] : mid[k];
    }
    std::vector<const BoundaryPoint*> inside;
    for (const BoundaryPoint* b : boundary)
      if ((b->point.array() >= clo.array()).all() && (b->point.array() <= chi.array()).all())
        inside.push_back(b);
    CutCellRule child =
        cut_cell_rule(probe, clo, chi, inside, settings, cell_volume, stats, depth + 1);
    rule.points.insert(rule.points.end(), child.points.begin(), child.points.end());
    rule.weights.insert(rule.weights.end(), child.weights.begin(), child.weights.end());
  }
  return rule;
}

}  // namespace isospring::geometry::detail
