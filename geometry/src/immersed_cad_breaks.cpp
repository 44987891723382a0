// Break points where the topology of a cut cell's lines changes (immersed_cad_breaks.hpp).
#include "immersed_cad_breaks.hpp"

#include <algorithm>

namespace isospring::geometry::detail {

namespace {

// The first change of `signature` among the samples and probes of [a, b] (its ends moved in by
// `inset`, and by `near_a` / `near_b` as well when positive), located to `resolution`; false
// when all samples agree.
bool first_change(double a, double b, const std::function<int(double)>& signature,
                  const std::vector<double>& samples, const std::vector<double>& probes,
                  double inset, double near_a, double near_b, double resolution, double& at) {
  std::vector<double> t{a + inset};
  if (near_a > 0.0) t.push_back(a + near_a);
  for (double s : samples) t.push_back(0.5 * (a + b) + 0.5 * (b - a) * s);
  for (double p : probes)
    if (p > a + inset && p < b - inset) t.push_back(p);
  t.push_back(b - inset);
  if (near_b > 0.0) t.push_back(b - near_b);
  std::sort(t.begin(), t.end());
  int previous = signature(t.front());
  for (size_t k = 1; k < t.size(); ++k) {
    const int current = signature(t[k]);
    if (current == previous) continue;
    double lo = t[k - 1], hi = t[k];
    while (hi - lo > resolution) {
      const double mid = 0.5 * (lo + hi);
      (signature(mid) == previous ? lo : hi) = mid;
    }
    at = 0.5 * (lo + hi);
    return true;
  }
  return false;
}

}  // namespace

std::vector<double> topology_breaks(const std::vector<double>& pieces,
                                    const std::function<int(double)>& signature,
                                    const std::vector<double>& samples, double resolution,
                                    double margin, const std::vector<double>& probes,
                                    int max_breaks) {
  margin = std::max(margin, resolution);
  // The box's own ends are also sampled this close: a curved face whose extreme lies within the
  // margin of the box's face (a cylinder poking 0.02 mm into a cell, the edges' tolerance 1e-5 m)
  // is a sliver that no sample a margin in sees. A change there is kept: the piece it cuts off is
  // as thin as the ambiguity, so a face merely on the box's face costs a thin piece, not
  // accuracy. Inner ends (crossings, where the boundary passes anyway) are not sampled so close:
  // lines there are ambiguous, and each would cost a bisection.
  const double close = std::min(10.0 * resolution, 0.25 * margin);
  const double front = pieces.front(), back = pieces.back();
  std::vector<double> done{pieces.front()};
  std::vector<std::pair<double, double>> unresolved;
  for (size_t k = pieces.size() - 1; k > 0; --k) unresolved.emplace_back(pieces[k - 1], pieces[k]);
  int added = 0;
  while (!unresolved.empty()) {
    const auto [a, b] = unresolved.back();
    unresolved.pop_back();
    double at = 0.0;
    // A piece shorter than a few margins holds no change worth a break.
    if (added < max_breaks && b - a > 4.0 * margin &&
        first_change(a, b, signature, samples, probes, margin, a == front ? close : 0.0,
                     b == back ? close : 0.0, resolution, at) &&
        at > a + (a == front ? close : margin) && at < b - (b == back ? close : margin)) {
      ++added;
      unresolved.emplace_back(at, b);
      unresolved.emplace_back(a, at);
      continue;
    }
    done.push_back(b);
  }
  return done;
}

}  // namespace isospring::geometry::detail
