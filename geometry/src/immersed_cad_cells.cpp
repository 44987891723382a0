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

// Lines on the box's faces are moved inside by a hair, so that a face of the part lying in the
// box's face plane is met on one side, not along the line.
Eigen::Vector3d hair(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  return 1e-9 * (hi - lo);
}

// The outer interval [lo[a], hi[a]] cut where the box's four edges along a (a = d + 1) cross the
// boundary and where the middle lines' crossings change in number (sampled at `samples`, Gauss
// abscissae on [-1, 1]): the same for every Gauss order, so found once per box.
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
  // The middle breaks' count at outer coordinate t (see immersed_cad_breaks.hpp): it changes
  // where a section curve of the boundary in the box's faces normal to d has a tangent along b.
  const auto middle_count = [&](double t) {
    int n = 0;
    for (double sd : {lo[d] + e[d], hi[d] - e[d]}) {
      Eigen::Vector3d p = lo;
      p[a] = t;
      p[d] = sd;
      n += static_cast<int>(probe.crossings(p, b, lo[b], hi[b]).size());
    }
    return n;
  };
  return topology_breaks(pieces(lo[a], hi[a], breaks), middle_count, samples,
                         1e-10 * (hi[a] - lo[a]));
}

// Dimension by dimension: outer axis a, middle axis b, lines along d (see immersed_cad.hpp).
CutCellRule line_rule(SolidProbe& probe, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                      int d, const std::vector<double>& outer, int order) {
  const int a = (d + 1) % 3, b = (d + 2) % 3;
  const Eigen::Vector3d e = hair(lo, hi);
  const std::array<double, 2> d_ends{lo[d] + e[d], hi[d] - e[d]};
  CutCellRule rule;
  const nurbs::GaussRule& g = nurbs::gauss_legendre_cached(order);
  rule.crossed = outer.size() > 2;
  int full = 0, empty = 0;  // lines wholly inside / outside the part
  for (size_t i = 0; i + 1 < outer.size(); ++i)
    for (size_t ga = 0; ga < g.points.size(); ++ga) {
      const double ha = 0.5 * (outer[i + 1] - outer[i]);
      const double xa = outer[i] + ha * (1.0 + g.points[ga]), wa = ha * g.weights[ga];
      std::vector<double> middle_breaks;
      for (double sd : d_ends) {
        Eigen::Vector3d p = lo;
        p[a] = xa;
        p[d] = sd;
        for (double t : probe.crossings(p, b, lo[b], hi[b])) middle_breaks.push_back(t);
      }
      const std::vector<double> middle = pieces(lo[b], hi[b], middle_breaks);
      if (middle.size() > 2) rule.crossed = true;
      for (size_t j = 0; j + 1 < middle.size(); ++j)
        for (size_t gb = 0; gb < g.points.size(); ++gb) {
          const double hb = 0.5 * (middle[j + 1] - middle[j]);
          const double xb = middle[j] + hb * (1.0 + g.points[gb]), wb = hb * g.weights[gb];
          Eigen::Vector3d p = lo;
          p[a] = xa;
          p[b] = xb;
          const std::vector<Interval> inside = probe.inside(p, d, lo[d], hi[d]);
          if (inside.empty())
            ++empty;
          else if (inside.size() == 1 && inside[0].lo <= lo[d] && inside[0].hi >= hi[d])
            ++full;
          else
            rule.crossed = true;
          for (const Interval& piece : inside)
            for (size_t gd = 0; gd < g.points.size(); ++gd) {
              const double hd = 0.5 * (piece.hi - piece.lo);
              p[d] = piece.lo + hd * (1.0 + g.points[gd]);
              rule.points.push_back(p);
              rule.weights.push_back(wa * wb * hd * g.weights[gd]);
            }
        }
    }
  if (full > 0 && empty > 0) rule.crossed = true;
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
