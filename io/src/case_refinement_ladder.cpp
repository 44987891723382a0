// k-refinement ladder of a case file (case_refinement_ladder.hpp).
#include "isospring/io/case_refinement_ladder.hpp"

#include <algorithm>

namespace isospring::io {

namespace {

// Degree elevation stops here: a degree-p basis couples (2p + 1)^d functions, so a degree-4
// solid has 729 couplings per function against 343 at degree 3 and its factorisation costs
// several times more for the same DOFs (measured: 49 s for 19,008 degree-4 DOFs).
int max_ladder_degree(int parametric_dimension) {
  return parametric_dimension >= 3 ? 3 : 4;
}

int parametric_dimension(const Case& c) {
  int dim = 1;
  for (const auto& patch : c.geometry) dim = std::max(dim, patch.param_dim());
  return dim;
}

}  // namespace

CaseDiscretization ladder_discretization(const Case& c, int level) {
  const int dim = parametric_dimension(c);
  CaseDiscretization disc = c.discretization;
  const int cap = max_ladder_degree(dim);
  int elevations = 0;  // levels spent raising degrees
  for (int d = 0; d < dim; ++d) elevations = std::max(elevations, cap - c.discretization.degree[d]);
  const int raise = std::min(level, elevations);
  for (int d = 0; d < dim; ++d)
    disc.degree[d] =
        std::max(c.discretization.degree[d], std::min(c.discretization.degree[d] + raise, cap));
  const int doublings = level - raise;
  for (int d = 0; d < dim; ++d) disc.elements[d] = c.discretization.elements[d] << doublings;
  return disc;
}

fitting::DiscretizationLadder case_refinement_ladder(const Case& c) {
  return [c](int level, std::string* description) -> std::optional<analysis::Problem> {
    if (level < 1 || level > 12) return std::nullopt;
    const CaseDiscretization disc = ladder_discretization(c, level);
    if (description) {
      const int dim = parametric_dimension(c);
      std::string degrees, elements;
      for (int d = 0; d < dim; ++d) {
        degrees += (d ? "," : "") + std::to_string(disc.degree[d]);
        elements += (d ? " x " : "") + std::to_string(disc.elements[d]);
      }
      *description = "degree " + degrees + ", " + elements + " elements";
    }
    return problem_at(c, disc);
  };
}

}  // namespace isospring::io
